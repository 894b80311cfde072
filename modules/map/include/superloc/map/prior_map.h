// The prior map: voxelized map points, the multi-resolution voxel map registration uses
// and the fine hash grid of bounded queries (PointGrid; the points are kept in its cell order),
// both built at load. A kd-tree is built by the first nearest-neighbour query; each point's
// normal, planarity, linearity and fit residual are computed by the first query of that point
// (both at load with MapParams::geometry_at_load).
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/core/types.h>
#include <superloc/map/point_grid.h>
#include <superloc/map/voxel_map.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace superloc::map {

/// Section [map] of the INI.
struct MapParams : public mrpt::config::CLoadableOptions {
    double voxel_size = 0.1;   ///< [m] voxel filter of the loaded map (0 = keep every point)
    int normal_k = 10;         ///< neighbours used for each point's normal/planarity
    double normal_max_radius = 1.0;  ///< [m] neighbours farther than this are not used
    // Registration voxel map (voxel_map.h, doc/map.md)
    double reg_voxel = 0.5;     ///< [m] finest level's voxel edge
    int reg_levels = 3;         ///< levels, each twice as coarse as the previous
    double reg_overlap = 0.0;   ///< dilation of each voxel per side, fraction of its edge (doc/map.md)
    int reg_min_points = 5;     ///< voxels with fewer map points are dropped
    // A tiled map (a directory of io/map_tiles.h): the tiles within tile_radius of the robot
    // are loaded, again whenever it has moved tile_reload from the last centre (doc/map.md).
    double tile_radius = 150;   ///< [m]
    double tile_reload = 40;    ///< [m]
    /// Every point's geometry (and the kd-tree) computed by the PriorMap's constructor, on all
    /// cores (PriorMap::prepareGeometry; a tiled map's tiles too, as they are loaded), instead of
    /// by the first query that meets the point: a frame then pays for no geometry. The values are
    /// the same either way; prepareSeconds() includes the time. On by default: a tracked frame
    /// then pays for no map point's geometry (KITTI's reference split: 16 -> 9 ms a frame).
    bool geometry_at_load = true;
    /// [m] cell edge of the fine hash grid (PointGrid) the `planes` association's fallback
    /// searches: the nearest map point within this distance in 27 cells, within twice it in 125
    /// at most (doc/map.md)
    double grid_cell = 0.5;

    VoxelMap::Params voxelMapParams() const { return {reg_voxel, reg_levels, reg_overlap, reg_min_points}; }

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
};

/// Geometry of one map point's neighbourhood (PCA of its normal_k neighbours).
struct PointGeometry {
    Vec3f normal = Vec3f::Zero();  ///< unit; oriented toward the viewpoint when one was known
    float planarity = 0;           ///< (l2 - l3) / l1 of the covariance eigenvalues l1>=l2>=l3
    float linearity = 0;           ///< (l1 - l2) / l1
    float fit_residual = 0;        ///< [m] RMS distance of the neighbours to the fitted plane
    bool oriented = false;         ///< normal sign is meaningful (viewpoint known)
};

/// PCA of a neighbourhood (Pauly et al. 2002 style): unsigned unit normal (eigenvector of the
/// smallest covariance eigenvalue), planarity, linearity and the RMS distance of the points to
/// their best-fit plane (= sqrt of the smallest eigenvalue). Fewer than 3 points, or all points
/// equal, give a zero normal, zero scores and an infinite fit_residual ("no geometry").
PointGeometry fitNeighborhood(const std::vector<Vec3f>& pts);

/// Result of a neighbourhood query.
struct Neighbors {
    std::vector<uint32_t> indices;  ///< nearest first
    std::vector<float> sq_dists;    ///< [m^2]
};

class PriorMap {
   public:
    /// Voxel-filters `cloud` (MapParams::voxel_size) and builds the registration voxel map (and,
    /// with MapParams::geometry_at_load, the kd-tree and every point's geometry).
    /// The per-point geometry (built on first use) has its normals flipped toward `viewpoint`
    /// when given (else toward the cloud's own normals when it had some; else left unsigned).
    PriorMap(const PointCloud& cloud, const MapParams& params,
             const std::optional<Vec3f>& viewpoint = std::nullopt);
    ~PriorMap();
    PriorMap(PriorMap&&) noexcept;
    PriorMap& operator=(PriorMap&&) noexcept;

    /// Loads a map file (any format of io::loadPointCloud) and prepares it.
    static PriorMap load(const std::string& path, const MapParams& params);

    size_t size() const;
    /// The voxel-filtered points in the point grid's cell order (PointGrid::cellOrder): with
    /// voxel_size 0, the given cloud's finite points permuted by cellOrder(them, grid_cell).
    const std::vector<Vec3f>& points() const;
    const Vec3f& point(size_t i) const;
    /// Per-point PCA geometry (normal_k neighbours within normal_max_radius), computed by the
    /// first call for that point; thread-safe. Throws std::out_of_range for a bad index.
    const PointGeometry& geometry(size_t i) const;
    /// Builds the kd-tree and computes every point's geometry now, on `threads` threads (0: one
    /// per core), so that no later query pays for it. The same values as computed on first use.
    /// Returns the seconds it took.
    double prepareGeometry(unsigned threads = 0) const;
    /// The registration map (association of the localizer).
    const VoxelMap& voxels() const;
    /// The fine hash grid of bounded nearest-neighbour queries (MapParams::grid_cell), built at
    /// load (the points are stored in its cell order); thread-safe.
    const PointGrid& grid() const;

    /// k nearest map points to q (fewer if the map is smaller); thread-safe. The first call
    /// builds the kd-tree.
    void knn(const Vec3f& q, size_t k, Neighbors& out) const;
    /// Nearest map point index and squared distance; thread-safe.
    std::pair<uint32_t, float> nearest(const Vec3f& q) const;

    /// Seconds spent voxelizing and building the voxel map (the lazy kd-tree not included).
    double prepareSeconds() const;
    /// Resident bytes of the points, the voxel map, the per-point geometry and (once built) the
    /// kd-tree.
    size_t memoryBytes() const;

   private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace superloc::map
