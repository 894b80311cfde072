#include <superloc/core/floor_int.h>
#include <superloc/core/voxel.h>
#include <superloc/features/voxel_selector.h>

#include <algorithm>

namespace superloc::features {

namespace {
// 21 bits per axis (±1M voxels): plenty for any LiDAR range at voxel >= 1 mm.
inline uint64_t packKey(const Vec3f& p, float inv) {
    // Finite points within the range filter's bounds: floorToInt is exact there.
    return packVoxelIndices(floorToInt(p.x() * inv), floorToInt(p.y() * inv), floorToInt(p.z() * inv));
}
}  // namespace

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

void VoxelSelector::firstPerVoxel(const std::vector<uint32_t>& idx, std::vector<uint32_t>& out) {
    // keys_[j] is the voxel of point idx[j].
    out.clear();
    // Keep the last frame's size (the next scan has about as many voxels).
    if (slots_.size() < 4096)
        slots_.assign(4096, kEmpty);
    else
        std::fill(slots_.begin(), slots_.end(), kEmpty);
    uint64_t mask = slots_.size() - 1;
    size_t used = 0;
    uint64_t last = kEmpty;  // consecutive points often share a voxel: no probe then
    for (size_t j = 0; j < idx.size(); ++j) {
        const uint64_t key = keys_[j];
        if (key == last) continue;
        last = key;
        uint64_t h = mixVoxelKey(key) & mask;
        while (slots_[h] != kEmpty && slots_[h] != key) h = (h + 1) & mask;
        if (slots_[h] == kEmpty) {
            slots_[h] = key;
            out.push_back(idx[j]);
            if (2 * (++used) > slots_.size()) {
                grow();  // rehashes the keys so far, this one included
                mask = slots_.size() - 1;
            }
        }
    }
}

void VoxelSelector::select(const std::vector<Vec3f>& points, const std::vector<uint32_t>& candidates,
                           float voxel, std::vector<uint32_t>& out) {
    const float inv = 1.0f / voxel;
    keys_.resize(candidates.size());
    for (size_t j = 0; j < candidates.size(); ++j) keys_[j] = packKey(points[candidates[j]], inv);
    firstPerVoxel(candidates, out);
}

void VoxelSelector::selectInRange(const std::vector<Vec3f>& points, float min_range, float max_range,
                                  float voxel, std::vector<uint32_t>& valid, std::vector<uint32_t>& out) {
    // The range test and the voxel keys in one pass over the points (a scan is read once, in order).
    const float r2min = min_range * min_range, r2max = max_range * max_range, inv = 1.0f / voxel;
    valid.clear();
    valid.reserve(points.size());
    keys_.resize(points.size());
    for (uint32_t i = 0; i < points.size(); ++i) {
        const float r2 = points[i].squaredNorm();
        if (r2 >= r2min && r2 <= r2max) {  // NaN compares false: dropped
            keys_[valid.size()] = packKey(points[i], inv);
            valid.push_back(i);
        }
    }
    firstPerVoxel(valid, out);
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
