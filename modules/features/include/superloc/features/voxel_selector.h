// Range filtering and voxel selection of a scan, allocation-free across frames: an
// open-addressing hash table that keeps its storage between calls (the per-frame hot path of
// the localizer; core's voxelDownsample is the general-purpose, allocating one).
#pragma once

#include <superloc/core/types.h>

#include <cstdint>
#include <vector>

namespace superloc::features {

class VoxelSelector {
   public:
    /// From the candidate indices, keeps the first point of every occupied voxel of size
    /// `voxel` (input order, so the result is deterministic and follows the firing order).
    /// `out` is cleared first.
    void select(const std::vector<Vec3f>& points, const std::vector<uint32_t>& candidates,
                float voxel, std::vector<uint32_t>& out);

    /// The indices of the finite points whose range lies in [min_range, max_range] (into
    /// `valid`) and select() of those (into `out`), in one pass over the points. Both are cleared
    /// first.
    void selectInRange(const std::vector<Vec3f>& points, float min_range, float max_range, float voxel,
                       std::vector<uint32_t>& valid, std::vector<uint32_t>& out);

   private:
    /// Open addressing, linear probing, kEmpty marks a free slot. Sized by the voxels found
    /// (at most half full, doubled when needed), not by the points: a 124k-point scan has ~11k
    /// occupied 0.5 m voxels, and a table that fits the cache is what makes the pass fast.
    std::vector<uint64_t> slots_;
    bool shortcut_ = true;  ///< FirstOfVoxel's test against the last voxel paid on the last call
    void grow();
    class FirstOfVoxel;  ///< one selection's pass over the table (voxel_selector.cpp)
};

/// At most `max_count` of `idx`, evenly strided over it (keeps the spatial spread of a
/// firing-ordered list); `out` is cleared first.
void takeEvenly(const std::vector<uint32_t>& idx, size_t max_count, std::vector<uint32_t>& out);

}  // namespace superloc::features
