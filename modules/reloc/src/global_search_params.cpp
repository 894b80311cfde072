// [global_search] section (doc/relocalization.md §4).
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/reloc/global_search.h>

#include <cmath>

namespace superloc::reloc {

BandGridPyramid::Params GlobalSearchParams::gridParams() const {
    BandGridPyramid::Params p;
    p.resolution = resolution;
    p.levels = levels;
    p.band_height = band_height;
    p.bands = bands;
    p.clearance = ground_clearance;
    p.z_tolerance = z_tolerance;
    p.dilate_cells = dilate_cells;
    p.ground_cell = ground_cell;
    p.position_margin = position_margin;
    return p;
}

GroundPlaneParams GlobalSearchParams::groundParams() const {
    GroundPlaneParams g;
    g.max_tilt_deg = ground_max_tilt_deg;
    g.inlier_dist = ground_inlier_dist;
    g.iterations = ground_iterations;
    return g;
}

void GlobalSearchParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(resolution, double, c, s);
    MRPT_LOAD_CONFIG_VAR(levels, int, c, s);
    MRPT_LOAD_CONFIG_VAR(band_height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(bands, int, c, s);
    MRPT_LOAD_CONFIG_VAR(ground_clearance, double, c, s);
    MRPT_LOAD_CONFIG_VAR(z_tolerance, double, c, s);
    MRPT_LOAD_CONFIG_VAR(dilate_cells, int, c, s);
    MRPT_LOAD_CONFIG_VAR(ground_cell, double, c, s);
    MRPT_LOAD_CONFIG_VAR(position_margin, double, c, s);
    MRPT_LOAD_CONFIG_VAR(yaw_step_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(min_range, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_range, double, c, s);
    MRPT_LOAD_CONFIG_VAR(scan_voxel, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_points, int, c, s);
    MRPT_LOAD_CONFIG_VAR(min_points, int, c, s);
    MRPT_LOAD_CONFIG_VAR(fallback_height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_hypotheses, int, c, s);
    MRPT_LOAD_CONFIG_VAR(nms_distance, double, c, s);
    MRPT_LOAD_CONFIG_VAR(nms_yaw_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(min_score, double, c, s);
    MRPT_LOAD_CONFIG_VAR(refine, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(refine_iterations, int, c, s);
    MRPT_LOAD_CONFIG_VAR(refine_inlier_dist, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ground_max_tilt_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ground_inlier_dist, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ground_iterations, int, c, s);
}

void GlobalSearchParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(resolution, "[m] finest search grid cell = translation step of the leaves");
    MRPT_SAVE_CONFIG_VAR_COMMENT(levels, "pyramid levels; the coarsest node spans 2^(levels-1) cells");
    MRPT_SAVE_CONFIG_VAR_COMMENT(band_height, "[m] height band above the local ground");
    MRPT_SAVE_CONFIG_VAR_COMMENT(bands, "height bands scored (<= 32), above ground_clearance");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ground_clearance, "[m] points lower than this above the ground are not scored");
    MRPT_SAVE_CONFIG_VAR_COMMENT(z_tolerance, "[m] a map point also marks the bands within this of its height");
    MRPT_SAVE_CONFIG_VAR_COMMENT(dilate_cells, "finest grid: a cell also holds its neighbours' bands within this");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ground_cell, "[m] column edge of the map's ground-height grid");
    MRPT_SAVE_CONFIG_VAR_COMMENT(position_margin, "[m] sensor positions searched: within this of observed ground");
    MRPT_SAVE_CONFIG_VAR_COMMENT(yaw_step_deg, "[deg] yaw step of the leaves");
    MRPT_SAVE_CONFIG_VAR_COMMENT(min_range, "[m] the search's own range filter (not [features]'s): closer scan points are dropped");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_range, "[m] ...and farther ones (the search scores the near scan only)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(scan_voxel, "[m] scan downsampling before the search");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_points, "scored scan points at most (taken evenly)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(min_points, "fewer scorable scan points: empty result");
    MRPT_SAVE_CONFIG_VAR_COMMENT(fallback_height, "[m] sensor height above ground when no ground plane is found");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_hypotheses, "distinct hypotheses returned at most (K)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(nms_distance, "[m] hypotheses closer than this and ...");
    MRPT_SAVE_CONFIG_VAR_COMMENT(nms_yaw_deg, "[deg] ... closer in yaw than this are one");
    MRPT_SAVE_CONFIG_VAR_COMMENT(min_score, "[-] hypotheses scoring less (fraction of scan points) are dropped");
    MRPT_SAVE_CONFIG_VAR_COMMENT(refine, "[bool] refine each hypothesis in 6-DoF (point-to-plane, voxel map)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(refine_iterations, "Gauss-Newton iterations per voxel-map level");
    MRPT_SAVE_CONFIG_VAR_COMMENT(refine_inlier_dist, "[m] point-to-plane residual of a refinement inlier");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ground_max_tilt_deg, "[deg] scan ground plane: normal within this of the lidar z axis");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ground_inlier_dist, "[m] scan ground plane: RANSAC inlier distance");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ground_iterations, "scan ground plane: RANSAC samples");
}

void GlobalSearchParams::validate() const {
    const auto need = [](bool ok, const std::string& what) {
        if (!ok) throw ConfigError("[global_search] " + what);
    };
    need(std::isfinite(resolution) && resolution >= 0.05 && resolution <= 5, "resolution must be in [0.05, 5] m");
    need(levels >= 1 && levels <= 12, "levels must be in [1, 12]");
    need(std::isfinite(band_height) && band_height > 0.05, "band_height must be > 0.05 m");
    need(bands >= 1 && bands <= 32, "bands must be in [1, 32] (one bit each)");
    need(std::isfinite(ground_clearance) && ground_clearance >= 0, "ground_clearance must be >= 0 m");
    need(std::isfinite(z_tolerance) && z_tolerance >= 0, "z_tolerance must be >= 0 m");
    need(dilate_cells >= 0 && dilate_cells <= 4, "dilate_cells must be in [0, 4]");
    need(std::isfinite(ground_cell) && ground_cell >= 0.2 && ground_cell <= 20, "ground_cell must be in [0.2, 20] m");
    need(std::isfinite(position_margin) && position_margin >= 0, "position_margin must be >= 0 m");
    need(std::isfinite(yaw_step_deg) && yaw_step_deg >= 0.1 && yaw_step_deg <= 30, "yaw_step_deg must be in [0.1, 30]");
    need(std::isfinite(min_range) && min_range >= 0, "min_range must be >= 0 m");
    need(std::isfinite(max_range) && max_range > min_range, "max_range must be > min_range");
    need(std::isfinite(scan_voxel) && scan_voxel >= 0, "scan_voxel must be >= 0 m");
    need(max_points >= 10, "max_points must be >= 10");
    need(min_points >= 1 && min_points <= max_points, "min_points must be in [1, max_points]");
    need(std::isfinite(fallback_height) && fallback_height >= 0, "fallback_height must be >= 0 m");
    need(max_hypotheses >= 1 && max_hypotheses <= 100, "max_hypotheses must be in [1, 100]");
    need(std::isfinite(nms_distance) && nms_distance >= 0, "nms_distance must be >= 0 m");
    need(std::isfinite(nms_yaw_deg) && nms_yaw_deg >= 0, "nms_yaw_deg must be >= 0");
    need(std::isfinite(min_score) && min_score >= 0 && min_score <= 1, "min_score must be in [0, 1]");
    need(refine_iterations >= 1 && refine_iterations <= 100, "refine_iterations must be in [1, 100]");
    need(std::isfinite(refine_inlier_dist) && refine_inlier_dist > 0, "refine_inlier_dist must be > 0 m");
    need(std::isfinite(ground_max_tilt_deg) && ground_max_tilt_deg > 0 && ground_max_tilt_deg < 90,
         "ground_max_tilt_deg must be in (0, 90)");
    need(std::isfinite(ground_inlier_dist) && ground_inlier_dist > 0, "ground_inlier_dist must be > 0 m");
    need(ground_iterations >= 1, "ground_iterations must be >= 1");
}

const char* toString(GravitySource s) {
    switch (s) {
        case GravitySource::Given: return "given";
        case GravitySource::GroundPlane: return "ground_plane";
        case GravitySource::AssumedLevel: return "assumed_level";
    }
    return "?";
}

}  // namespace superloc::reloc
