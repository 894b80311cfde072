// Global localization without an initial pose (doc/relocalization.md): a
// gravity-aligned 4-DoF search (x, y, yaw; z from the map's ground height + the scan's own
// height above its ground plane) by branch-and-bound over the max-pooled height-band grids of
// BandGridPyramid, then a short point-to-plane refinement of each hypothesis in the map's
// registration voxel map (6-DoF). Returns up to K distinct hypotheses, best first, with the
// scores a caller needs to call the answer unique or ambiguous.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/system/COutputLogger.h>
#include <superloc/core/types.h>
#include <superloc/reloc/band_grid.h>
#include <superloc/reloc/ground_plane.h>

#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace superloc::map {
class PriorMap;
}

namespace superloc::reloc {

/// Section [global_search] of the INI.
struct GlobalSearchParams : public mrpt::config::CLoadableOptions {
    // Search grids (built once per map)
    double resolution = 0.25;      ///< [m] finest grid cell = translation step of the leaves
    int levels = 7;                ///< pyramid levels; the coarsest node spans 2^(levels-1) cells
    double band_height = 0.5;      ///< [m] height band above the local ground
    int bands = 24;                ///< bands scored (<= 32): up to bands * band_height above clearance
    double ground_clearance = 0.3; ///< [m] points lower than this above the ground are not scored
    double z_tolerance = 0.25;     ///< [m] a map point also marks the bands within this of its height
    int dilate_cells = 1;          ///< finest grid: a cell also holds its neighbours' bands within this
    double ground_cell = 1.0;      ///< [m] column edge of the map's ground-height grid
    double position_margin = 3.0;  ///< [m] sensor positions searched: within this of observed ground
    // Query
    double yaw_step_deg = 1.5;     ///< [deg] yaw step of the leaves
    double min_range = 1.0;        ///< [m] scan points closer than this are dropped
    double max_range = 40.0;       ///< [m] and farther than this
    double scan_voxel = 0.4;       ///< [m] scan downsampling before the search
    int max_points = 1200;         ///< scored scan points at most (taken evenly)
    int min_points = 50;           ///< fewer scorable points: empty result
    double fallback_height = 1.5;  ///< [m] sensor height above ground when no ground plane is found
    int max_hypotheses = 5;        ///< K: distinct hypotheses returned at most
    double nms_distance = 2.0;     ///< [m] hypotheses closer than this ...
    double nms_yaw_deg = 20.0;     ///< [deg] ... and closer in yaw than this are one
    double min_score = 0.15;       ///< [-] hypotheses scoring less (fraction of points) are dropped
    // Refinement of each hypothesis (point-to-plane in the map's registration voxel map)
    bool refine = true;            ///< refine each hypothesis in 6-DoF
    int refine_iterations = 10;    ///< Gauss-Newton iterations per voxel-map level
    double refine_inlier_dist = 0.2; ///< [m] point-to-plane residual of an inlier
    // Ground plane (gravity from the scan when no IMU)
    double ground_max_tilt_deg = 45;  ///< [deg] ground normal within this of the lidar z axis
    double ground_inlier_dist = 0.1;  ///< [m] RANSAC inlier distance
    int ground_iterations = 200;      ///< RANSAC samples

    BandGridPyramid::Params gridParams() const;
    GroundPlaneParams groundParams() const;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    /// Throws ConfigError naming [global_search] and the key when a value is out of range.
    void validate() const;
};

/// Restricts a search (the local wide search after a loss): sensor positions within a disc and
/// yaws within an interval.
struct SearchRegion {
    Vec3d centre = Vec3d::Zero();  ///< [m] map frame; z is ignored
    double radius = 10;            ///< [m] horizontal
    double yaw = 0;                ///< [rad] centre of the yaw interval (ZYX yaw of T_map_lidar)
    double yaw_half_width = M_PI;  ///< [rad] half width; >= pi = every yaw
};

/// One candidate pose.
struct PoseHypothesis {
    SE3d T_map_lidar = SE3d::Identity();
    /// [-] fraction of the scored scan points that hit an occupied band cell of the finest grid
    /// at T_map_lidar (bands from the map's own ground under each point). Comparable across
    /// the hypotheses of one query, not across scans.
    double score = 0;
    double search_score = 0;  ///< [-] the same fraction at the branch-and-bound leaf (before refining)
    SE3d T_map_lidar_search = SE3d::Identity();  ///< the leaf pose (z from the ground grid)
    /// [-] this hypothesis' score over the best one's (1 for the best).
    double ratio_to_best = 1;
    // Refinement (when GlobalSearchParams::refine)
    bool refined = false;       ///< the refinement ran and settled
    double fit_inliers = 0;     ///< [-] fraction of refinement points within refine_inlier_dist of a plane
    double fit_rms = 0;         ///< [m] RMS residual of those inliers
};

enum class GravitySource {
    Given,        ///< R_level_lidar from the caller (IMU)
    GroundPlane,  ///< estimated from the scan's ground plane
    AssumedLevel  ///< no ground plane found: the lidar assumed level
};
const char* toString(GravitySource s);

/// What one query found.
struct GlobalSearchResult {
    std::vector<PoseHypothesis> hypotheses;  ///< best first; empty when nothing scored min_score
    /// Runner-up's score over the best's (0 with fewer than 2 hypotheses). Near 1: the scan fits
    /// two distinct places equally well (aliasing, a corridor): do not commit to the first. The
    /// Localizer's lost-frame search verifies every hypothesis within [relocalization]
    /// ambiguity_ratio of the best (doc/relocalization.md).
    double runner_up_ratio = 0;
    GravitySource gravity = GravitySource::AssumedLevel;
    Mat3d R_level_lidar = Mat3d::Identity();  ///< roll/pitch used (zero yaw)
    double sensor_height = 0;  ///< [m] lidar above its ground plane used for the bands and z
    size_t points_in = 0;      ///< valid points given
    size_t points_scored = 0;  ///< scan points scored by the search
    size_t yaws = 0;           ///< yaw steps searched
    size_t nodes = 0;          ///< branch-and-bound nodes scored (all levels)
    size_t leaves = 0;         ///< leaves scored
    double seconds = 0;        ///< wall time of the query
    std::string failure;       ///< why there is no hypothesis ("" when there is one)
};

/// The global search over one prior map. Build once; search() is const and thread-safe.
class GlobalSearch : public mrpt::system::COutputLogger {
   public:
    /// Builds the ground and band grids from the map's points; keeps a reference to `map`
    /// (its registration voxel map refines the hypotheses), which must outlive this object.
    GlobalSearch(const map::PriorMap& map, const GlobalSearchParams& params);

    /// Global (region = nullptr) or regional search for a scan with no initial pose.
    /// `points_lidar`: the scan in the lidar frame (NaN/out-of-range points are dropped).
    /// `R_level_lidar`: the lidar's roll/pitch w.r.t. gravity (map z) when an IMU knows it (its
    /// yaw is ignored); absent: estimated from the scan's ground plane.
    GlobalSearchResult search(const std::vector<Vec3f>& points_lidar,
                              const std::optional<Mat3d>& R_level_lidar = std::nullopt,
                              const SearchRegion* region = nullptr) const;

    /// Score (as PoseHypothesis::score) of the scan at a given pose: for checks and tests.
    double scoreAt(const std::vector<Vec3f>& points_lidar, const SE3d& T_map_lidar) const;

    const GlobalSearchParams& params() const { return params_; }
    const BandGridPyramid& grid() const { return grid_; }
    double buildSeconds() const { return build_seconds_; }
    /// Resident bytes of the search grids (the map itself not included).
    size_t memoryBytes() const { return grid_.memoryBytes(); }

   private:
    const map::PriorMap& map_;
    GlobalSearchParams params_;
    BandGridPyramid grid_;
    double build_seconds_ = 0;
};

}  // namespace superloc::reloc
