// The registration map: a multi-resolution hashed voxel map of the prior map (doc/map.md).
//
// Each level is a grid of cubic voxels of edge `size`; a voxel stores the statistics of the map
// points inside its cube *dilated* by `overlap * size` on every side (mean, covariance shape,
// plane normal, line direction, plane thickness). Because neighbouring voxels share the points
// near their common faces, the voxel that contains a query point describes the surface around
// that point even when the point sits on a voxel face: association is one hash probe per query
// and level, O(1) whatever the map's size, instead of a kd-tree search.
//
// Coarse levels (metres) give registration a wide basin, as NDT's 1 m cells do; the finest
// level gives the accuracy. Built once at load, in time and memory linear in the map's points
// (nothing per point is kept).
#pragma once

#include <superloc/core/floor_int.h>
#include <superloc/core/types.h>
#include <superloc/core/voxel.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace superloc::map {

/// Statistics of the map points in one (dilated) voxel. 60 bytes.
struct VoxelStats {
    Vec3f mean = Vec3f::Zero();       ///< [m] centroid
    Vec3f normal = Vec3f::Zero();     ///< unit, eigenvector of the smallest eigenvalue (unsigned)
    Vec3f direction = Vec3f::Zero();  ///< unit, eigenvector of the largest eigenvalue
    float planarity = 0;              ///< (l2 - l3) / l1
    float linearity = 0;              ///< (l1 - l2) / l1
    float thickness = 0;              ///< [m] RMS distance of the points to their plane, sqrt(l3)
    /// [m] the points' RMS spread in the plane: along `direction` (sqrt(l1)) and along
    /// normal x direction (sqrt(l2)); the plane's footprint for the `planes` association
    float spread_major = 0, spread_minor = 0;
    float count = 0;                  ///< points in the (dilated) voxel
};

struct VoxelLevelInfo {
    double size = 0;        ///< [m] voxel edge
    size_t voxels = 0;      ///< voxels with at least min_points points
    size_t table_bytes = 0; ///< hash table size
};

class VoxelMap {
   public:
    struct Params {
        double finest = 0.5;    ///< [m] edge of the finest level's voxels
        int levels = 3;         ///< number of levels; each is twice as coarse as the previous
        double overlap = 0.0;   ///< dilation of each voxel's cube per side, as a fraction of its edge
        int min_points = 5;     ///< voxels with fewer points are dropped
    };

    VoxelMap() = default;
    /// Builds every level from `points` (any density). Throws std::invalid_argument for bad params.
    VoxelMap(const std::vector<Vec3f>& points, const Params& params);

    int levels() const { return static_cast<int>(levels_.size()); }
    double levelSize(int level) const { return levels_.at(static_cast<size_t>(level)).size; }
    /// Statistics of the voxel containing x at `level` (0 = finest), or nullptr when it is empty.
    inline const VoxelStats* find(int level, const Vec3f& x) const;
    /// Asks the CPU to fetch the table slot find(level, x) starts at (a query a few ahead of the
    /// current one: the probe then finds it in cache). No effect on any answer.
    inline void prefetch(int level, const Vec3f& x) const;

    std::vector<VoxelLevelInfo> info() const;
    /// Resident bytes of all levels (tables and statistics).
    size_t memoryBytes() const;
    const Params& params() const { return params_; }

   private:
    struct Slot {
        uint64_t key = kEmpty;
        VoxelStats stats;
    };
    static constexpr uint64_t kEmpty = ~0ull;
    struct Level {
        double size = 0;
        float inv = 0;
        std::vector<Slot> table;  ///< open addressing, linear probing; power-of-two size
        uint64_t mask = 0;
        size_t count = 0;
    };
    void buildLevel(const std::vector<Vec3f>& points, Level& level) const;
    /// The key of the voxel containing x at level L; false for an empty level, or an x not
    /// finite or out of the key range.
    static inline bool keyOf(const Level& L, const Vec3f& x, uint64_t& key);

    Params params_;
    std::vector<Level> levels_;
};

// ---------------------------------------------------------------------------------------------

inline bool VoxelMap::keyOf(const Level& L, const Vec3f& x, uint64_t& key) {
    if (L.table.empty()) return false;
    const Vec3f s = x * L.inv;
    if (!s.allFinite() || s.cwiseAbs().maxCoeff() > float(1 << 20) - 2) return false;
    key = packVoxelIndices(floorToInt(s.x()), floorToInt(s.y()), floorToInt(s.z()));
    return true;
}

inline const VoxelStats* VoxelMap::find(int level, const Vec3f& x) const {
    const Level& L = levels_[static_cast<size_t>(level)];
    uint64_t key;
    if (!keyOf(L, x, key)) return nullptr;
    for (uint64_t h = mixVoxelKey(key) & L.mask;; h = (h + 1) & L.mask) {
        const Slot& slot = L.table[h];
        if (slot.key == key) return &slot.stats;
        if (slot.key == kEmpty) return nullptr;
    }
}

inline void VoxelMap::prefetch(int level, const Vec3f& x) const {
    const Level& L = levels_[static_cast<size_t>(level)];
    uint64_t key;
    if (keyOf(L, x, key)) __builtin_prefetch(&L.table[mixVoxelKey(key) & L.mask]);
}

}  // namespace superloc::map
