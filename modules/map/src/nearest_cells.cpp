// NearestCells (nearest_cells.h): a flat open-addressing table of cells, each holding the map
// points nearest to its centre.
#include <superloc/core/floor_int.h>
#include <superloc/map/nearest_cells.h>
#include <superloc/map/prior_map.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace superloc::map {

namespace {
constexpr uint64_t kEmpty = ~0ull;
inline uint64_t mixKey(uint64_t k) {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdULL;
    k ^= k >> 33;
    return k;
}
inline uint64_t packCell(int64_t x, int64_t y, int64_t z) {
    const auto q = [](int64_t v) { return static_cast<uint64_t>(v + (1 << 20)) & 0x1FFFFFu; };
    return (q(x) << 42) | (q(y) << 21) | q(z);
}
}  // namespace

NearestCells::NearestCells(double edge, size_t max_cells)
    : edge_(edge), inv_(static_cast<float>(1.0 / edge)), max_cells_(std::max<size_t>(max_cells, 16)) {
    if (!(edge > 0) || !std::isfinite(edge)) throw std::invalid_argument("NearestCells: edge must be > 0 m");
    slots_.resize(1024);
    mask_ = slots_.size() - 1;
}

void NearestCells::grow() {
    std::vector<Slot> old(slots_.size() * 2);
    old.swap(slots_);
    mask_ = slots_.size() - 1;
    for (const Slot& s : old) {
        if (s.key == kEmpty) continue;
        for (size_t h = mixKey(s.key) & mask_;; h = (h + 1) & mask_)
            if (slots_[h].key == kEmpty) {
                slots_[h] = s;
                break;
            }
    }
}

NearestCells::Slot& NearestCells::fill(const PriorMap& map, uint64_t key, const int64_t k[3], size_t h) {
    ++misses_;
    if (count_ + 1 > max_cells_) {  // emptied, not evicted: the answers are recomputed as asked
        std::fill(slots_.begin(), slots_.end(), Slot{});
        count_ = 0;
        h = mixKey(key) & mask_;
    } else if (2 * (count_ + 1) > slots_.size()) {
        grow();
        h = mixKey(key) & mask_;
        while (slots_[h].key != kEmpty) h = (h + 1) & mask_;
    }
    Slot& s = slots_[h];
    s.key = key;
    ++count_;
    const Vec3f centre((static_cast<float>(k[0]) + 0.5f) * static_cast<float>(edge_),
                       (static_cast<float>(k[1]) + 0.5f) * static_cast<float>(edge_),
                       (static_cast<float>(k[2]) + 0.5f) * static_cast<float>(edge_));
    map.knn(centre, kCandidates, nb_);
    s.count = static_cast<uint32_t>(nb_.indices.size());
    for (uint32_t i = 0; i < s.count; ++i) {
        const Vec3f& p = map.point(nb_.indices[i]);
        s.c[i] = {{p.x(), p.y(), p.z()}, nb_.indices[i]};
    }
    return s;
}

std::pair<uint32_t, float> NearestCells::nearest(const PriorMap& map, const Vec3f& x) {
    constexpr std::pair<uint32_t, float> none{std::numeric_limits<uint32_t>::max(),
                                              std::numeric_limits<float>::infinity()};
    const Vec3f s = x * inv_;
    if (map.size() == 0 || !s.allFinite() || s.cwiseAbs().maxCoeff() > float(1 << 20) - 2) return none;
    ++queries_;
    const int64_t k[3] = {floorToInt(s.x()), floorToInt(s.y()), floorToInt(s.z())};
    const uint64_t key = packCell(k[0], k[1], k[2]);
    size_t h = mixKey(key) & mask_;
    while (slots_[h].key != key && slots_[h].key != kEmpty) h = (h + 1) & mask_;
    const Slot& slot = slots_[h].key == key ? slots_[h] : fill(map, key, k, h);
    std::pair<uint32_t, float> best = none;
    for (uint32_t i = 0; i < slot.count; ++i) {
        const float dx = slot.c[i].p[0] - x.x(), dy = slot.c[i].p[1] - x.y(), dz = slot.c[i].p[2] - x.z();
        const float d2 = dx * dx + dy * dy + dz * dz;
        if (d2 < best.second) best = {slot.c[i].index, d2};
    }
    return best;
}

}  // namespace superloc::map
