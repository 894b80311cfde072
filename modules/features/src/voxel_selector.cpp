#include <superloc/core/floor_int.h>
#include <superloc/core/voxel.h>
#include <superloc/features/voxel_selector.h>

#include <algorithm>
#include <limits>

namespace superloc::features {

// A key uses 63 bits (3 x 21), so all ones is never one.
constexpr uint64_t kEmpty = ~0ULL;

void VoxelSelector::grow() {
    std::vector<uint64_t> old;
    old.swap(slots_);
    slots_.assign(old.size() * 2, kEmpty);
    const uint64_t mask = slots_.size() - 1;
    for (uint64_t key : old) {
        if (key == kEmpty) continue;
        uint64_t h = mixVoxelKey(key) & mask;
        while (slots_[h] != kEmpty) h = (h + 1) & mask;
        slots_[h] = key;
    }
}

/// The first point of each voxel, in the order the points are offered (VoxelSelector's table,
/// cleared): offer() says whether a point is its voxel's first. In a LiDAR's firing order
/// consecutive points often share a voxel (82 % of a KITTI scan's at 0.5 m): then neither key nor
/// probe, only the point's scaled coordinates against the last voxel's [lo, lo + 1) per axis
/// (exact: the indices of finite points within the range filter are far below 2^24, and beyond it
/// the interval is empty). Clouds in another order (campus-ouster's scans: 1 %) pay that test for
/// nothing, so it is used only where it paid on the selector's last call (same answer either way).
class VoxelSelector::FirstOfVoxel {
   public:
    FirstOfVoxel(VoxelSelector& sel, float voxel) : sel_(sel), inv_(1.0f / voxel), shortcut_(sel.shortcut_) {
        // Keep the last frame's size (the next scan has about as many voxels).
        if (sel_.slots_.size() < 4096)
            sel_.slots_.assign(4096, kEmpty);
        else
            std::fill(sel_.slots_.begin(), sel_.slots_.end(), kEmpty);
        slots_ = sel_.slots_.data();
        mask_ = sel_.slots_.size() - 1;
    }
    /// The next call's choice: the shortcut where a quarter of the points shared their
    /// predecessor's voxel.
    ~FirstOfVoxel() { sel_.shortcut_ = offered_ == 0 || 4 * same_ >= offered_; }
    bool offer(const Vec3f& p) {
        ++offered_;
        const Vec3f q = p * inv_;
        if (shortcut_ && q.x() >= lo_.x() && q.x() < lo_.x() + 1.0f && q.y() >= lo_.y() &&
            q.y() < lo_.y() + 1.0f && q.z() >= lo_.z() && q.z() < lo_.z() + 1.0f) {
            ++same_;
            return false;
        }
        const int64_t ix = floorToInt(q.x()), iy = floorToInt(q.y()), iz = floorToInt(q.z());
        if (shortcut_) lo_ = Vec3f(static_cast<float>(ix), static_cast<float>(iy), static_cast<float>(iz));
        const uint64_t key = packVoxelIndices(ix, iy, iz);
        if (key == last_) {
            ++same_;
            return false;
        }
        last_ = key;
        uint64_t h = mixVoxelKey(key) & mask_;
        while (slots_[h] != kEmpty && slots_[h] != key) h = (h + 1) & mask_;
        if (slots_[h] != kEmpty) return false;
        slots_[h] = key;
        if (2 * (++used_) > mask_ + 1) {
            sel_.grow();  // rehashes the keys so far, this one included
            slots_ = sel_.slots_.data();
            mask_ = sel_.slots_.size() - 1;
        }
        return true;
    }

   private:
    VoxelSelector& sel_;
    float inv_;
    bool shortcut_;                     ///< the [lo, lo + 1) test first
    size_t offered_ = 0, same_ = 0;     ///< points offered; of those, in their predecessor's voxel
    uint64_t* slots_ = nullptr;  ///< sel_.slots_'s, again after each grow()
    uint64_t mask_ = 0;
    size_t used_ = 0;
    uint64_t last_ = kEmpty;
    Vec3f lo_ = Vec3f::Constant(std::numeric_limits<float>::quiet_NaN());  // compares false: no voxel yet
};

void VoxelSelector::select(const std::vector<Vec3f>& points, const std::vector<uint32_t>& candidates,
                           float voxel, std::vector<uint32_t>& out) {
    out.clear();
    FirstOfVoxel first(*this, voxel);
    for (uint32_t i : candidates)
        if (first.offer(points[i])) out.push_back(i);
}

void VoxelSelector::selectInRange(const std::vector<Vec3f>& points, float min_range, float max_range,
                                  float voxel, std::vector<uint32_t>& valid, std::vector<uint32_t>& out) {
    // The range test and the selection in one pass over the points (a scan is read once, in order).
    const float r2min = min_range * min_range, r2max = max_range * max_range;
    valid.clear();
    valid.reserve(points.size());
    out.clear();
    FirstOfVoxel first(*this, voxel);
    const uint32_t n = static_cast<uint32_t>(points.size());
    for (uint32_t i = 0; i < n; ++i) {
        const float r2 = points[i].squaredNorm();
        if (!(r2 >= r2min && r2 <= r2max)) continue;  // NaN compares false: dropped
        valid.push_back(i);
        if (first.offer(points[i])) out.push_back(i);
    }
}

void takeEvenly(const std::vector<uint32_t>& idx, size_t max_count, std::vector<uint32_t>& out) {
    out.clear();
    if (idx.size() <= max_count) {
        out = idx;
        return;
    }
    out.reserve(max_count);
    const double step = static_cast<double>(idx.size()) / static_cast<double>(max_count);
    for (size_t k = 0; k < max_count; ++k) out.push_back(idx[static_cast<size_t>(k * step)]);
}

}  // namespace superloc::features
