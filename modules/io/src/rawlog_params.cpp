// [rawlog] section: observation labels, reorder window, per-point time from azimuth.
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/io/rawlog.h>

#include <cmath>

namespace superloc::io {

void RawlogParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                      const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(odom_alt_label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(gt_label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(lidar_label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(imu_label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(reorder_window, double, c, s);
    MRPT_LOAD_CONFIG_VAR(scan_period, double, c, s);
    MRPT_LOAD_CONFIG_VAR(rotation_sense, int, c, s);
    MRPT_LOAD_CONFIG_VAR(start_azimuth_deg, double, c, s);
}

void RawlogParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(odom_alt_label, "CObservationRobotPose label of the 2nd odometry");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gt_label, "CObservationRobotPose label of ground truth");
    MRPT_SAVE_CONFIG_VAR_COMMENT(lidar_label, "LiDAR sensor label to use (empty = all)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(imu_label, "IMU sensor label to use (empty = all)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(reorder_window, "[s] out-of-order tolerance (re-sort window)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(scan_period, "[s] sweep period for per-point time (0 = none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rotation_sense, "+1 counter-clockwise from above, -1 clockwise");
    MRPT_SAVE_CONFIG_VAR_COMMENT(start_azimuth_deg, "[deg] azimuth of a sweep's first firing");
}

void RawlogParams::validate() const {
    if (!(reorder_window >= 0) || !std::isfinite(reorder_window))
        throw ConfigError("[rawlog] reorder_window must be >= 0 seconds");
    if (!(scan_period >= 0) || !std::isfinite(scan_period))
        throw ConfigError("[rawlog] scan_period must be >= 0 seconds (0 disables per-point time)");
    if (rotation_sense != 1 && rotation_sense != -1)
        throw ConfigError("[rawlog] rotation_sense must be +1 or -1");
    if (!std::isfinite(start_azimuth_deg))
        throw ConfigError("[rawlog] start_azimuth_deg must be finite");
    if (odom_alt_label.empty() || gt_label.empty())
        throw ConfigError("[rawlog] odom_alt_label and gt_label must not be empty");
    if (odom_alt_label == gt_label)
        throw ConfigError("[rawlog] odom_alt_label and gt_label must differ");
}

}  // namespace superloc::io
