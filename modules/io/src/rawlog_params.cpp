// [rawlog] section: observation labels, reorder window, per-point time from azimuth.
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/io/rawlog.h>

#include <cmath>
#include <cstdint>
#include <string>

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
    MRPT_LOAD_CONFIG_VAR(scans, string, c, s);
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
    MRPT_SAVE_CONFIG_VAR_COMMENT(scans, "LiDAR scans read: all | even | odd | FIRST:END[:STEP]");
}

RawlogParams::ScanSelection RawlogParams::scanSelection() const {
    ScanSelection sel;
    if (scans == "all") return sel;
    if (scans == "even" || scans == "odd") {
        sel.first = scans == "odd" ? 1 : 0;
        sel.step = 2;
        return sel;
    }
    const auto bad = [this] {
        return ConfigError("[rawlog] scans: '" + scans +
                           "' is not all, even, odd or FIRST:END[:STEP] (e.g. 0:100 or 100::1)");
    };
    size_t fields[3] = {0, SIZE_MAX, 1};
    size_t k = 0, start = 0;
    for (size_t i = 0; i <= scans.size(); ++i) {
        if (i < scans.size() && scans[i] != ':') continue;
        if (k > 2) throw bad();
        const std::string f = scans.substr(start, i - start);
        if (!f.empty()) {
            if (f.find_first_not_of("0123456789") != std::string::npos || f.size() > 12) throw bad();
            fields[k] = std::stoull(f);
        } else if (k == 0 || k == 2) {
            throw bad();
        }
        ++k;
        start = i + 1;
    }
    if (k < 2 || fields[2] == 0 || fields[1] <= fields[0]) throw bad();
    sel.first = fields[0];
    sel.end = fields[1];
    sel.step = fields[2];
    return sel;
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
    scanSelection();
}

}  // namespace superloc::io
