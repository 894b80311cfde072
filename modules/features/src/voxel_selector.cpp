#include <superloc/features/voxel_selector.h>

#include <cmath>
#include <cstring>

namespace superloc::features {

void rangeFilter(const std::vector<Vec3f>& points, float min_range, float max_range,
                 std::vector<uint32_t>& out) {
    out.clear();
    out.reserve(points.size());
    const float r2min = min_range * min_range, r2max = max_range * max_range;
    for (uint32_t i = 0; i < points.size(); ++i) {
        const float r2 = points[i].squaredNorm();
        // NaN compares false: dropped.
        if (r2 >= r2min && r2 <= r2max) out.push_back(i);
    }
}

namespace {
// 21 bits per axis (±1M voxels): plenty for any LiDAR range at voxel >= 1 mm.
inline uint64_t packKey(const Vec3f& p, float inv) {
    const auto q = [inv](float v) {
        return static_cast<uint64_t>(static_cast<int64_t>(std::floor(v * inv)) + (1 << 20)) &
               0x1FFFFFu;
    };
    return (q(p.x()) << 42) | (q(p.y()) << 21) | q(p.z());
}
inline uint64_t mix(uint64_t k) {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdULL;
    k ^= k >> 33;
    return k;
}
}  // namespace

void VoxelSelector::select(const std::vector<Vec3f>& points, const std::vector<uint32_t>& candidates,
                           float voxel, std::vector<uint32_t>& out) {
    out.clear();
    size_t cap = 1024;
    while (cap < 2 * candidates.size()) cap <<= 1;
    if (keys_.size() != cap) {
        keys_.assign(cap, 0);
        used_.assign(cap, 0);
    } else {
        std::memset(used_.data(), 0, used_.size());
    }
    const uint64_t mask = cap - 1;
    const float inv = 1.0f / voxel;
    for (uint32_t i : candidates) {
        const uint64_t key = packKey(points[i], inv);
        uint64_t h = mix(key) & mask;
        while (used_[h] && keys_[h] != key) h = (h + 1) & mask;
        if (!used_[h]) {
            used_[h] = 1;
            keys_[h] = key;
            out.push_back(i);
        }
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
