// PointGrid: points sorted by cell, one hash slot per occupied cell; bounded 27-cell queries.
#include <superloc/core/floor_int.h>
#include <superloc/core/voxel.h>
#include <superloc/map/point_grid.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace superloc::map {

namespace {
constexpr float kMaxIndex = float(1 << 20) - 4;  // packVoxelIndices is exact within +-2^20

/// The offsets of the cells `ring` cells away (the 26 around a cell for ring 1, the 98 around
/// those for ring 2), those sharing a face with the inner cells first, then edges, then corners:
/// the nearer boxes first, so that the best distance shrinks early and prunes the far ones.
std::vector<std::array<int, 3>> ringOffsets(int ring) {
    std::vector<std::array<int, 3>> o;
    for (int nonzero = 1; nonzero <= 3; ++nonzero)
        for (int dx = -ring; dx <= ring; ++dx)
            for (int dy = -ring; dy <= ring; ++dy)
                for (int dz = -ring; dz <= ring; ++dz) {
                    const int m = std::max({std::abs(dx), std::abs(dy), std::abs(dz)});
                    const int far = (std::abs(dx) == ring) + (std::abs(dy) == ring) + (std::abs(dz) == ring);
                    if (m == ring && far == nonzero) o.push_back({dx, dy, dz});
                }
    return o;
}
const std::vector<std::array<int, 3>>& neighbourOffsets(int ring) {
    static const std::vector<std::array<int, 3>> one = ringOffsets(1), two = ringOffsets(2);
    return ring == 1 ? one : two;
}
}  // namespace

namespace {
/// Each point's cell key, or ~0 for a point outside the key range or not finite.
std::vector<uint64_t> cellKeys(const std::vector<Vec3f>& points, float inv) {
    std::vector<uint64_t> keys(points.size(), ~0ull);
    for (size_t i = 0; i < points.size(); ++i) {
        const Vec3f s = points[i] * inv;
        if (!s.allFinite() || s.cwiseAbs().maxCoeff() > kMaxIndex) continue;
        keys[i] = packVoxelIndices(floorToInt(s.x()), floorToInt(s.y()), floorToInt(s.z()));
    }
    return keys;
}
}  // namespace

std::vector<uint32_t> PointGrid::cellOrder(const std::vector<Vec3f>& points, double cell) {
    if (!(cell > 0) || !std::isfinite(cell)) throw std::invalid_argument("PointGrid: cell must be > 0 m");
    const std::vector<uint64_t> keys = cellKeys(points, static_cast<float>(1.0 / cell));
    std::vector<uint32_t> order(points.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<uint32_t>(i);
    std::stable_sort(order.begin(), order.end(), [&keys](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
    return order;
}

PointGrid::PointGrid(const std::vector<Vec3f>& points, double cell) : cell_(cell), pts_(&points) {
    if (!(cell > 0) || !std::isfinite(cell)) throw std::invalid_argument("PointGrid: cell must be > 0 m");
    inv_ = static_cast<float>(1.0 / cell);
    const std::vector<uint64_t> keys = cellKeys(points, inv_);
    // In cell order already (PriorMap's points): the cells are ranges of the points themselves.
    const bool ordered = std::is_sorted(keys.begin(), keys.end());
    if (!ordered) index_ = cellOrder(points, cell);
    const auto keyAt = [&](size_t j) { return keys[ordered ? j : index_[j]]; };
    size_t n = 0;  // points inside the grid's range (the others sort last)
    while (n < keys.size() && keyAt(n) != ~0ull) ++n;
    if (!ordered) index_.resize(n);
    for (size_t j = 0; j < n; ++j)
        if (j == 0 || keyAt(j) != keyAt(j - 1)) ++count_;
    size_t cap = 16;
    while (cap < 2 * count_) cap <<= 1;
    table_.assign(cap, Slot{});
    mask_ = cap - 1;
    for (size_t j = 0; j < n;) {
        size_t e = j;
        const uint64_t key = keyAt(j);
        while (e < n && keyAt(e) == key) ++e;
        for (uint64_t h = mixVoxelKey(key) & mask_;; h = (h + 1) & mask_)
            if (table_[h].key == ~0ull) {
                table_[h] = Slot{key, static_cast<uint32_t>(j), static_cast<uint32_t>(e)};
                break;
            }
        j = e;
    }
}

const PointGrid::Slot* PointGrid::find(int64_t x, int64_t y, int64_t z) const {
    const uint64_t key = packVoxelIndices(x, y, z);
    for (uint64_t h = mixVoxelKey(key) & mask_;; h = (h + 1) & mask_) {
        const Slot& s = table_[h];
        if (s.key == key) return &s;
        if (s.key == ~0ull) return nullptr;
    }
}

template <class Visit, class Bound>
void PointGrid::forCells(const Vec3f& q, int rings, Visit&& visit, Bound&& bound) const {
    if (table_.empty()) return;
    const Vec3f s = q * inv_;
    if (!s.allFinite() || s.cwiseAbs().maxCoeff() > kMaxIndex - 2) return;
    const int64_t c[3] = {floorToInt(s.x()), floorToInt(s.y()), floorToInt(s.z())};
    // Distance [m] from q to the lower and the upper face of its cell, per axis.
    const float edge = static_cast<float>(cell_);
    float lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        const float f = s[k] - static_cast<float>(c[k]);
        lo[k] = f * edge;
        hi[k] = (1.0f - f) * edge;
    }
    if (const Slot* own = find(c[0], c[1], c[2])) visit(own->begin, own->end);
    for (int ring = 1; ring <= rings; ++ring)
        for (const auto& o : neighbourOffsets(ring)) {
            float box = 0;  // squared distance from q to the cell's box
            for (int k = 0; k < 3; ++k) {
                const int a = std::abs(o[k]);
                const float d = a == 0 ? 0.0f : (o[k] < 0 ? lo[k] : hi[k]) + static_cast<float>(a - 1) * edge;
                box += d * d;
            }
            if (box >= bound()) continue;
            if (const Slot* n = find(c[0] + o[0], c[1] + o[1], c[2] + o[2])) visit(n->begin, n->end);
        }
}

namespace {
/// Rings of cells a search of radius r needs (1 or 2), and r clamped to what they cover.
int ringsFor(float& r, double cell) {
    const float edge = static_cast<float>(cell);
    r = std::min(r, 2.0f * edge);
    return r > edge ? 2 : 1;
}
}  // namespace

std::pair<uint32_t, float> PointGrid::nearest(const Vec3f& q, float max_dist, uint32_t hint) const {
    float r = max_dist;
    const int rings = ringsFor(r, cell_);
    float best = r * r;
    uint32_t best_i = kNone;
    const std::vector<Vec3f>& pts = *pts_;
    if (hint < pts.size()) {
        // Any point bounds the search: a nearer one lies in a cell whose box is nearer still.
        const float d2 = (pts[hint] - q).squaredNorm();
        if (d2 <= best) best = d2, best_i = hint;
    }
    forCells(
        q, rings,
        [&](uint32_t b, uint32_t e) {
            for (uint32_t j = b; j < e; ++j) {
                const uint32_t i = index_.empty() ? j : index_[j];
                const float d2 = (pts[i] - q).squaredNorm();
                if (d2 <= best) best = d2, best_i = i;
            }
        },
        [&] { return best; });
    if (best_i == kNone) return {kNone, std::numeric_limits<float>::infinity()};
    return {best_i, best};
}

void PointGrid::knn(const Vec3f& q, size_t k, float max_dist, std::vector<uint32_t>& idx,
                    std::vector<float>& sq_dists) const {
    idx.clear();
    sq_dists.clear();
    if (k == 0) return;
    float r = max_dist;
    const int rings = ringsFor(r, cell_);
    const float r2 = r * r;
    // Sorted, at most k: (squared distance, point index).
    std::vector<std::pair<float, uint32_t>> best;
    best.reserve(k + 1);
    const std::vector<Vec3f>& pts = *pts_;
    forCells(
        q, rings,
        [&](uint32_t b, uint32_t e) {
            for (uint32_t j = b; j < e; ++j) {
                const uint32_t i = index_.empty() ? j : index_[j];
                const float d2 = (pts[i] - q).squaredNorm();
                if (d2 > r2 || (best.size() == k && d2 >= best.back().first)) continue;
                const auto at = std::upper_bound(best.begin(), best.end(), std::make_pair(d2, i));
                best.insert(at, {d2, i});
                if (best.size() > k) best.pop_back();
            }
        },
        [&] { return best.size() == k ? best.back().first : r2; });
    for (const auto& [d2, i] : best) {
        idx.push_back(i);
        sq_dists.push_back(d2);
    }
}

size_t PointGrid::memoryBytes() const {
    return table_.capacity() * sizeof(Slot) + index_.capacity() * sizeof(uint32_t);
}

}  // namespace superloc::map
