// VoxelMap: per-level accumulation of point statistics over dilated voxel cubes, then one
// 3x3 eigen decomposition per voxel (doc/map.md).
#include <superloc/map/voxel_map.h>

#include <Eigen/Eigenvalues>
#include <functional>
#include <stdexcept>
#include <string>

namespace superloc::map {

namespace {
/// Running sums of the points in one dilated voxel, relative to the voxel's corner (so the
/// sums stay small and the covariance keeps its precision far from the map origin).
struct Accum {
    uint64_t key = ~0ull;
    double n = 0;
    double s[3] = {0, 0, 0};
    double ss[6] = {0, 0, 0, 0, 0, 0};  ///< xx xy xz yy yz zz
};

/// Open-addressing table of accumulators that grows as voxels appear.
class AccumTable {
   public:
    AccumTable() : slots_(4096), mask_(4095) {}
    Accum& at(uint64_t key, uint64_t hash) {
        if (2 * (count_ + 1) > slots_.size()) grow();
        for (uint64_t h = hash & mask_;; h = (h + 1) & mask_) {
            Accum& a = slots_[h];
            if (a.key == key) return a;
            if (a.key == ~0ull) {
                a.key = key;
                ++count_;
                return a;
            }
        }
    }
    const std::vector<Accum>& slots() const { return slots_; }
    std::function<uint64_t(uint64_t)> hash;

   private:
    void grow() {
        std::vector<Accum> old(slots_.size() * 2);
        old.swap(slots_);
        mask_ = slots_.size() - 1;
        for (const Accum& a : old) {
            if (a.key == ~0ull) continue;
            for (uint64_t h = hash(a.key) & mask_;; h = (h + 1) & mask_)
                if (slots_[h].key == ~0ull) {
                    slots_[h] = a;
                    break;
                }
        }
    }
    std::vector<Accum> slots_;
    uint64_t mask_;
    size_t count_ = 0;
};
}  // namespace

VoxelMap::VoxelMap(const std::vector<Vec3f>& points, const Params& params) : params_(params) {
    if (!(params.finest > 0) || !std::isfinite(params.finest))
        throw std::invalid_argument("VoxelMap: finest voxel size must be > 0 m");
    if (params.levels < 1 || params.levels > 8)
        throw std::invalid_argument("VoxelMap: levels must be in [1, 8]");
    if (!(params.overlap >= 0 && params.overlap < 0.5))
        throw std::invalid_argument("VoxelMap: overlap must be in [0, 0.5)");
    if (params.min_points < 3) throw std::invalid_argument("VoxelMap: min_points must be >= 3");
    levels_.resize(static_cast<size_t>(params.levels));
    for (int l = 0; l < params.levels; ++l) {
        Level& L = levels_[static_cast<size_t>(l)];
        L.size = params.finest * std::pow(2.0, l);
        L.inv = static_cast<float>(1.0 / L.size);
        buildLevel(points, L);
    }
}

void VoxelMap::buildLevel(const std::vector<Vec3f>& points, Level& L) const {
    AccumTable acc;
    acc.hash = [](uint64_t k) { return mixVoxelKey(k); };
    const double inv = 1.0 / L.size;
    const double ov = params_.overlap;
    for (const Vec3f& pf : points) {
        if (!pf.allFinite()) continue;
        const Vec3d p = pf.cast<double>() * inv;  // in voxel units
        if (p.cwiseAbs().maxCoeff() > double(1 << 20) - 4) continue;
        int64_t lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
            const double f = std::floor(p[k]);
            const double frac = p[k] - f;
            lo[k] = static_cast<int64_t>(f) - (frac < ov ? 1 : 0);
            hi[k] = static_cast<int64_t>(f) + (frac > 1.0 - ov ? 1 : 0);
        }
        for (int64_t x = lo[0]; x <= hi[0]; ++x)
            for (int64_t y = lo[1]; y <= hi[1]; ++y)
                for (int64_t z = lo[2]; z <= hi[2]; ++z) {
                    const uint64_t key = packVoxelIndices(x, y, z);
                    Accum& a = acc.at(key, mixVoxelKey(key));
                    // Relative to the voxel corner, in metres.
                    const double d[3] = {(p[0] - double(x)) * L.size, (p[1] - double(y)) * L.size,
                                         (p[2] - double(z)) * L.size};
                    a.n += 1;
                    a.s[0] += d[0], a.s[1] += d[1], a.s[2] += d[2];
                    a.ss[0] += d[0] * d[0], a.ss[1] += d[0] * d[1], a.ss[2] += d[0] * d[2];
                    a.ss[3] += d[1] * d[1], a.ss[4] += d[1] * d[2], a.ss[5] += d[2] * d[2];
                }
    }
    // Count the voxels kept, then fill a table at load factor <= 0.5.
    size_t kept = 0;
    for (const Accum& a : acc.slots())
        if (a.key != ~0ull && a.n >= params_.min_points) ++kept;
    size_t cap = 16;
    while (cap < 2 * kept) cap <<= 1;
    L.table.assign(kept ? cap : 0, Slot{});
    L.mask = cap - 1;
    L.count = kept;
    Eigen::SelfAdjointEigenSolver<Mat3d> es;
    for (const Accum& a : acc.slots()) {
        if (a.key == ~0ull || a.n < params_.min_points) continue;
        const Vec3d m(a.s[0] / a.n, a.s[1] / a.n, a.s[2] / a.n);
        Mat3d C;
        C << a.ss[0], a.ss[1], a.ss[2], a.ss[1], a.ss[3], a.ss[4], a.ss[2], a.ss[4], a.ss[5];
        C = C / a.n - m * m.transpose();
        es.computeDirect(C);
        const Vec3d ev = es.eigenvalues().cwiseMax(0.0);  // ascending: l3 l2 l1
        VoxelStats st;
        const int64_t kx = static_cast<int64_t>((a.key >> 42) & 0x1FFFFFu) - (1 << 20);
        const int64_t ky = static_cast<int64_t>((a.key >> 21) & 0x1FFFFFu) - (1 << 20);
        const int64_t kz = static_cast<int64_t>(a.key & 0x1FFFFFu) - (1 << 20);
        const Vec3d corner = Vec3d(double(kx), double(ky), double(kz)) * L.size;
        st.mean = (corner + m).cast<float>();
        if (ev(2) > 1e-12) {
            st.normal = es.eigenvectors().col(0).normalized().cast<float>();
            st.direction = es.eigenvectors().col(2).normalized().cast<float>();
            st.planarity = static_cast<float>((ev(1) - ev(0)) / ev(2));
            st.linearity = static_cast<float>((ev(2) - ev(1)) / ev(2));
            st.thickness = static_cast<float>(std::sqrt(ev(0)));
            st.spread_minor = static_cast<float>(std::sqrt(ev(1)));
            st.spread_major = static_cast<float>(std::sqrt(ev(2)));
        }
        st.count = static_cast<float>(a.n);
        for (uint64_t h = mixVoxelKey(a.key) & L.mask;; h = (h + 1) & L.mask)
            if (L.table[h].key == kEmpty) {
                L.table[h].key = a.key;
                L.table[h].stats = st;
                break;
            }
    }
}

std::vector<VoxelLevelInfo> VoxelMap::info() const {
    std::vector<VoxelLevelInfo> out;
    for (const Level& L : levels_) out.push_back({L.size, L.count, L.table.size() * sizeof(Slot)});
    return out;
}

size_t VoxelMap::memoryBytes() const {
    size_t b = sizeof(*this);
    for (const Level& L : levels_) b += L.table.capacity() * sizeof(Slot);
    return b;
}

}  // namespace superloc::map
