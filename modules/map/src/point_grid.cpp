// PointGrid: points sorted by cell, one hash slot per occupied cell; bounded 27-cell queries.
#include <superloc/core/floor_int.h>
#include <superloc/core/voxel.h>
#include <superloc/map/point_grid.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace superloc::map {

namespace {
constexpr float kMaxIndex = float(1 << 20) - 4;  // packVoxelIndices is exact within +-2^20

/// q's cell indices c and q in cell units s; false for a q not finite or within two cells of the
/// key range's end (a query's neighbours must be packable too).
bool queryCell(const Vec3f& q, float inv, Vec3f& s, int64_t c[3]) {
    s = q * inv;
    if (!s.allFinite() || s.cwiseAbs().maxCoeff() > kMaxIndex - 2) return false;
    c[0] = floorToInt(s.x()), c[1] = floorToInt(s.y()), c[2] = floorToInt(s.z());
    return true;
}

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

void PointGrid::prefetch(const Vec3f& q) const {
    Vec3f s;
    int64_t c[3];
    if (table_.empty() || !queryCell(q, inv_, s, c)) return;
    __builtin_prefetch(&table_[mixVoxelKey(packVoxelIndices(c[0], c[1], c[2])) & mask_]);
}

void PointGrid::prefetchPoints(const Vec3f& q) const {
    Vec3f s;
    int64_t c[3];
    if (table_.empty() || !queryCell(q, inv_, s, c)) return;
    const Slot* own = find(c[0], c[1], c[2]);
    if (!own || own->begin == own->end) return;
    // The cell's first points (its slot should be in cache: prefetch() asked for it earlier);
    // in cell order only (a cell's points contiguous).
    if (!index_.empty()) return;
    const char* b = reinterpret_cast<const char*>(pts_->data() + own->begin);
    const char* e = reinterpret_cast<const char*>(pts_->data() + own->end);
    for (const char* a = b; a < e && a < b + 256; a += 64) __builtin_prefetch(a);
}

template <class Visit, class Bound>
float PointGrid::forCells(const Vec3f& q, int rings, Visit&& visit, Bound&& bound) const {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    Vec3f s;
    int64_t c[3];
    if (table_.empty() || !queryCell(q, inv_, s, c)) return 0.0f;
    // Per axis, the squared distance [m^2] from q to the slab of the cells o = -2..2 away along it
    // (0 for its own): lo / hi is q's distance to its cell's lower / upper face.
    const float edge = static_cast<float>(cell_);
    float axis2[3][5];
    float nearest_face = edge;
    for (int k = 0; k < 3; ++k) {
        const float f = s[k] - static_cast<float>(c[k]);
        const float lo = f * edge, hi = (1.0f - f) * edge;
        nearest_face = std::min({nearest_face, lo, hi});
        axis2[k][0] = (lo + edge) * (lo + edge);
        axis2[k][1] = lo * lo;
        axis2[k][2] = 0.0f;
        axis2[k][3] = hi * hi;
        axis2[k][4] = (hi + edge) * (hi + edge);
    }
    if (const Slot* own = find(c[0], c[1], c[2])) visit(own->begin, own->end);
    // The cells around, nearest box first, each only while its box is nearer than the best point
    // found so far. A ring is skipped whole when even its nearest box (q's nearest face, plus
    // the ring's inner cells) is not nearer: with a good bound (a hint, or a point of q's own
    // cell) that leaves a few cells at most. `unvisited`: the nearest box of a cell passed over.
    float unvisited = kInf;
    struct Near {
        float box;
        int8_t o[3];
    };
    Near todo[124];
    for (int ring = 1; ring <= rings; ++ring) {
        const float inner = nearest_face + static_cast<float>(ring - 1) * edge;
        if (inner * inner >= bound()) {
            unvisited = std::min(unvisited, inner * inner);  // this ring's cells and the next's
            break;
        }
        // Per axis, the offsets whose slab is nearer than the bound.
        int from[3], to[3];
        const float b = bound();
        for (int k = 0; k < 3; ++k) {
            from[k] = -ring, to[k] = ring;
            while (from[k] < 0 && axis2[k][from[k] + 2] >= b) ++from[k];
            while (to[k] > 0 && axis2[k][to[k] + 2] >= b) --to[k];
            // A cell of this ring beyond a slab left out is at least that slab away.
            if (from[k] > -ring) unvisited = std::min(unvisited, axis2[k][from[k] + 1]);
            if (to[k] < ring) unvisited = std::min(unvisited, axis2[k][to[k] + 3]);
        }
        int n = 0;
        for (int dx = from[0]; dx <= to[0]; ++dx)
            for (int dy = from[1]; dy <= to[1]; ++dy)
                for (int dz = from[2]; dz <= to[2]; ++dz) {
                    if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != ring) continue;
                    const float box = axis2[0][dx + 2] + axis2[1][dy + 2] + axis2[2][dz + 2];
                    if (box >= b) {
                        unvisited = std::min(unvisited, box);
                        continue;
                    }
                    // Insertion into the list sorted by box (a few cells, usually).
                    int at = n++;
                    for (; at > 0 && todo[at - 1].box > box; --at) todo[at] = todo[at - 1];
                    todo[at] = Near{box, {static_cast<int8_t>(dx), static_cast<int8_t>(dy), static_cast<int8_t>(dz)}};
                }
        for (int i = 0; i < n; ++i) {
            if (todo[i].box >= bound()) {  // sorted: the rest are farther still
                unvisited = std::min(unvisited, todo[i].box);
                break;
            }
            if (const Slot* cell = find(c[0] + todo[i].o[0], c[1] + todo[i].o[1], c[2] + todo[i].o[2]))
                visit(cell->begin, cell->end);
        }
    }
    return unvisited;
}

namespace {
/// Rings of cells a search of radius r needs (1 or 2), and r clamped to what they cover.
int ringsFor(float& r, double cell) {
    const float edge = static_cast<float>(cell);
    r = std::min(r, 2.0f * edge);
    return r > edge ? 2 : 1;
}
}  // namespace

std::pair<uint32_t, float> PointGrid::nearest(const Vec3f& q, float max_dist, uint32_t hint, float* second) const {
    float r = max_dist;
    const int rings = ringsFor(r, cell_);
    float best = r * r, next = r * r;  // the nearest's squared distance, and the next measured one's
    uint32_t best_i = kNone;
    const std::vector<Vec3f>& pts = *pts_;
    if (hint < pts.size()) {
        // Any point bounds the search: a nearer one lies in a cell whose box is nearer still.
        const float d2 = (pts[hint] - q).squaredNorm();
        if (d2 <= best) best = d2, best_i = hint;
    } else {
        hint = kNone;
    }
    const float unvisited = forCells(
        q, rings,
        [&](uint32_t b, uint32_t e) {
            for (uint32_t j = b; j < e; ++j) {
                const uint32_t i = index_.empty() ? j : index_[j];
                if (i == hint) continue;  // measured before the visits
                const float d2 = (pts[i] - q).squaredNorm();
                // Equally near points: the lowest index, whichever cell was visited first.
                if (d2 < best || (d2 == best && i < best_i)) {
                    if (best_i != kNone) next = std::min(next, best);
                    best = d2, best_i = i;
                } else {
                    next = std::min(next, d2);
                }
            }
        },
        [&] { return best; });
    if (second) *second = std::min(next, unvisited);
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
                if (d2 > r2 || (best.size() == k && std::make_pair(d2, i) >= best.back())) continue;
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
