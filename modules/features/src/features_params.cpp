#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/features/features_params.h>

namespace superloc::features {

void FeaturesParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(min_range, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_range, double, c, s);
    MRPT_LOAD_CONFIG_VAR(deskew, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(deskew_imu_poses, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(deskew_without_imu, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(voxel_size, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_features, int, c, s);
    MRPT_LOAD_CONFIG_VAR(plane_max_thickness, double, c, s);
    MRPT_LOAD_CONFIG_VAR(line_min_linearity, double, c, s);
}

void FeaturesParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(min_range, "[m] drop points closer than this");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_range, "[m] drop points farther than this");
    MRPT_SAVE_CONFIG_VAR_COMMENT(deskew, "undo the sweep motion (per-point time needed)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(deskew_imu_poses, "with IMU: deskew along its integrated poses");
    MRPT_SAVE_CONFIG_VAR_COMMENT(deskew_without_imu, "no IMU: also deskew with the constant-velocity prediction (odom_alt's motion deskews anyway)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(voxel_size, "[m] one candidate point per voxel");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_features, "max features per scan, spread over candidates");
    MRPT_SAVE_CONFIG_VAR_COMMENT(plane_max_thickness, "[-] map neighbourhood l3/l2 below: plane");
    MRPT_SAVE_CONFIG_VAR_COMMENT(line_min_linearity, "[-] linearity above (not plane): line feature");
}

void FeaturesParams::validate() const {
    if (!(min_range >= 0)) throw ConfigError("[features] min_range must be >= 0");
    if (!(max_range > min_range)) throw ConfigError("[features] max_range must be > min_range");
    if (!(voxel_size > 0)) throw ConfigError("[features] voxel_size must be > 0");
    if (max_features < 10) throw ConfigError("[features] max_features must be >= 10");
    if (!(plane_max_thickness >= 0 && plane_max_thickness <= 1))
        throw ConfigError("[features] plane_max_thickness must be in [0, 1]");
    if (!(line_min_linearity >= 0 && line_min_linearity <= 1))
        throw ConfigError("[features] line_min_linearity must be in [0, 1]");
}

}  // namespace superloc::features
