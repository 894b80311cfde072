#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/localization/localization_params.h>

#include <cmath>

namespace superloc::localization {

Method methodFromString(const std::string& s) {
    if (s == "icp") return Method::Icp;
    if (s == "ndt") return Method::Ndt;
    if (s == "superloc") return Method::SuperLoc;
    if (s == "superloc_paper") return Method::SuperLocPaper;
    if (s == "passive") return Method::Passive;
    if (s == "eigen_remap") return Method::EigenRemap;
    throw ConfigError("[localization] method = '" + s +
                      "' is unknown (use icp, ndt, superloc, superloc_paper, passive or eigen_remap)");
}

const char* methodName(Method m) {
    switch (m) {
        case Method::Icp: return "icp";
        case Method::Ndt: return "ndt";
        case Method::SuperLoc: return "superloc";
        case Method::SuperLocPaper: return "superloc_paper";
        case Method::Passive: return "passive";
        case Method::EigenRemap: return "eigen_remap";
    }
    return "?";
}

void LocalizationParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    method = methodFromString(c.read_string(s, "method", methodName(method)));
    MRPT_LOAD_CONFIG_VAR(use_imu, bool, c, s);
    output_frame = c.read_string(s, "output_frame", output_frame);
    MRPT_LOAD_CONFIG_VAR(max_corr_dist, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_corr_dist_init, double, c, s);
    MRPT_LOAD_CONFIG_VAR(rounds, int, c, s);
    MRPT_LOAD_CONFIG_VAR(rounds_init, int, c, s);
    MRPT_LOAD_CONFIG_VAR(max_cv_gap, double, c, s);
    MRPT_LOAD_CONFIG_VAR(motion_from_last_scan, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(last_scan_yaw_step, double, c, s);
    MRPT_LOAD_CONFIG_VAR(last_scan_features, int, c, s);
    MRPT_LOAD_CONFIG_VAR(sweep_velocity, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(converged_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(converged_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(settle_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(settle_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(settle_after_scan, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(inlier_dist, double, c, s);
    MRPT_LOAD_CONFIG_VAR(min_inlier_ratio, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_jump_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_jump_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ndt_resolution, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ndt_step_size, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ndt_epsilon, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ndt_max_iterations, int, c, s);
}

void LocalizationParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    c.write(s, "method", std::string(methodName(method)), mrpt::config::MRPT_SAVE_NAME_PADDING(),
            mrpt::config::MRPT_SAVE_VALUE_PADDING(), "icp | ndt | superloc | superloc_paper | passive | eigen_remap");
    MRPT_SAVE_CONFIG_VAR_COMMENT(use_imu, "IMU prediction + preintegration factor when available");
    MRPT_SAVE_CONFIG_VAR_COMMENT(output_frame, "reported poses: lidar (T_map_lidar) or body");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_corr_dist, "[m] max distance to the map point (nearest, planes) / voxel plane (voxel, finest level)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_corr_dist_init, "[m] nearest, planes: the same on a wide frame's first rounds");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rounds, "most association + solve rounds per tracked frame");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rounds_init, "most rounds of a frame started at the coarsest level");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_cv_gap, "[s] no IMU: a longer gap means unknown velocity (coarse start)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(motion_from_last_scan, "no IMU: unknown velocity measured against the last scan first");
    MRPT_SAVE_CONFIG_VAR_COMMENT(last_scan_yaw_step, "[deg] that motion's first guess: turns about the vertical in these steps (0: none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(last_scan_features, "that registration's features: every k-th, at most this many (0: all)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(sweep_velocity, "unknown velocity, timed points: estimate the sweep's velocity for deskew");
    MRPT_SAVE_CONFIG_VAR_COMMENT(converged_xyz, "[m] stop when the round's update is below");
    MRPT_SAVE_CONFIG_VAR_COMMENT(converged_deg, "[deg] ...and the rotation update below");
    MRPT_SAVE_CONFIG_VAR_COMMENT(settle_xyz, "[m] tracked frame: a round's update below this (and settle_deg) ends the kernel's annealing; 0: off");
    MRPT_SAVE_CONFIG_VAR_COMMENT(settle_deg, "[deg] ...and the rotation update below");
    MRPT_SAVE_CONFIG_VAR_COMMENT(settle_after_scan, "no IMU: a frame whose motion the last (sound) scan measured may settle too");
    MRPT_SAVE_CONFIG_VAR_COMMENT(inlier_dist, "[m] feature residual below: inlier");
    MRPT_SAVE_CONFIG_VAR_COMMENT(min_inlier_ratio, "[-] inlier ratio below: diverged");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_jump_xyz, "[m] solved vs predicted farther: diverged");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_jump_deg, "[deg] solved vs predicted rotation: diverged");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ndt_resolution, "[m] NDT cell size (method=ndt)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ndt_step_size, "[m] NDT line-search step");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ndt_epsilon, "NDT transformation epsilon");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ndt_max_iterations, "NDT max iterations");
}

void LocalizationParams::validate() const {
    if (output_frame != "lidar" && output_frame != "body")
        throw ConfigError("[localization] output_frame = '" + output_frame + "' (use lidar or body)");
    const auto positive = [](double v, const char* key) {
        if (!(v > 0)) throw ConfigError(std::string("[localization] ") + key + " must be > 0");
    };
    positive(max_corr_dist, "max_corr_dist");
    positive(max_corr_dist_init, "max_corr_dist_init");
    if (!(last_scan_yaw_step >= 0 && last_scan_yaw_step <= 180))
        throw ConfigError("[localization] last_scan_yaw_step must be in [0, 180] deg");
    if (last_scan_features < 0) throw ConfigError("[localization] last_scan_features must be >= 0 (0: all)");
    if (rounds < 1) throw ConfigError("[localization] rounds must be >= 1");
    if (rounds_init < 1) throw ConfigError("[localization] rounds_init must be >= 1");
    positive(max_cv_gap, "max_cv_gap");
    positive(converged_xyz, "converged_xyz");
    positive(converged_deg, "converged_deg");
    if (!(settle_xyz >= 0) || !std::isfinite(settle_xyz)) throw ConfigError("[localization] settle_xyz must be >= 0");
    if (!(settle_deg >= 0) || !std::isfinite(settle_deg)) throw ConfigError("[localization] settle_deg must be >= 0");
    positive(inlier_dist, "inlier_dist");
    if (!(min_inlier_ratio >= 0 && min_inlier_ratio <= 1))
        throw ConfigError("[localization] min_inlier_ratio must be in [0, 1]");
    positive(max_jump_xyz, "max_jump_xyz");
    positive(max_jump_deg, "max_jump_deg");
    positive(ndt_resolution, "ndt_resolution");
    positive(ndt_step_size, "ndt_step_size");
    positive(ndt_epsilon, "ndt_epsilon");
    if (ndt_max_iterations < 1) throw ConfigError("[localization] ndt_max_iterations must be >= 1");
}

}  // namespace superloc::localization
