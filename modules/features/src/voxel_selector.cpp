#include <superloc/features/voxel_selector.h>

#include <cmath>
#include <algorithm>

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
    // floor() without the libm call (no SSE4.1 assumed): truncate, then step down for
    // negatives. The same integer for every finite v * inv in int range, which the range
    // filter guarantees.
    const auto q = [inv](float v) {
        const float s = v * inv;
        int64_t i = static_cast<int64_t>(s);
        i -= static_cast<float>(i) > s;
        return static_cast<uint64_t>(i + (1 << 20)) & 0x1FFFFFu;
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

// A key uses 63 bits (3 x 21), so all ones is never one.
constexpr uint64_t kEmpty = ~0ULL;

void VoxelSelector::grow() {
    std::vector<uint64_t> old;
    old.swap(slots_);
    slots_.assign(old.size() * 2, kEmpty);
    const uint64_t mask = slots_.size() - 1;
    for (uint64_t key : old) {
        if (key == kEmpty) continue;
        uint64_t h = mix(key) & mask;
        while (slots_[h] != kEmpty) h = (h + 1) & mask;
        slots_[h] = key;
    }
}

void VoxelSelector::select(const std::vector<Vec3f>& points, const std::vector<uint32_t>& candidates,
                           float voxel, std::vector<uint32_t>& out) {
    out.clear();
    // Keep the last frame's size (the next scan has about as many voxels).
    if (slots_.size() < 4096)
        slots_.assign(4096, kEmpty);
    else
        std::fill(slots_.begin(), slots_.end(), kEmpty);
    uint64_t mask = slots_.size() - 1;
    size_t used = 0;
    const float inv = 1.0f / voxel;
    uint64_t last = kEmpty;  // consecutive points of a ring often share a voxel: no probe then
    for (uint32_t i : candidates) {
        const uint64_t key = packKey(points[i], inv);
        if (key == last) continue;
        last = key;
        uint64_t h = mix(key) & mask;
        while (slots_[h] != kEmpty && slots_[h] != key) h = (h + 1) & mask;
        if (slots_[h] == kEmpty) {
            slots_[h] = key;
            out.push_back(i);
            if (2 * (++used) > slots_.size()) {
                grow();  // rehashes the keys so far, this one included
                mask = slots_.size() - 1;
            }
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
