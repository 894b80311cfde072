// [rosbag] section: topic -> observation mapping, frames, per-point time (superloc-import --rosbag).
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/io/rosbag.h>

#include <cmath>
#include <sstream>

namespace superloc::io {

void RosbagParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                      const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(lidar_topic, string, c, s);
    MRPT_LOAD_CONFIG_VAR(imu_topic, string, c, s);
    MRPT_LOAD_CONFIG_VAR(odom_alt_topic, string, c, s);
    MRPT_LOAD_CONFIG_VAR(gt_topic, string, c, s);
    MRPT_LOAD_CONFIG_VAR(tf_static_topic, string, c, s);
    MRPT_LOAD_CONFIG_VAR(lidar_label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(imu_label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(odom_alt_label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(gt_label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(body_frame, string, c, s);
    MRPT_LOAD_CONFIG_VAR(lidar_extrinsic, string, c, s);
    MRPT_LOAD_CONFIG_VAR(gt_child_frame, string, c, s);
    MRPT_LOAD_CONFIG_VAR(point_time_field, string, c, s);
    MRPT_LOAD_CONFIG_VAR(point_time_unit, string, c, s);
    MRPT_LOAD_CONFIG_VAR(point_time_reference, string, c, s);
    MRPT_LOAD_CONFIG_VAR(intensity_max, double, c, s);
    MRPT_LOAD_CONFIG_VAR(stamp_source, string, c, s);
    MRPT_LOAD_CONFIG_VAR(max_clock_offset, double, c, s);
    for (std::string* v : {&lidar_topic, &imu_topic, &odom_alt_topic, &gt_topic, &tf_static_topic,
                           &lidar_label, &imu_label, &odom_alt_label, &gt_label, &body_frame,
                           &lidar_extrinsic, &gt_child_frame, &point_time_field, &point_time_unit,
                           &point_time_reference, &stamp_source})
        *v = stripIniValue(*v);
}

void RosbagParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(lidar_topic, "sensor_msgs/PointCloud2 topic (empty = auto, none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(imu_topic, "sensor_msgs/Imu topic (empty = auto, none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(odom_alt_topic, "nav_msgs/Odometry topic -> odom_alt (none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gt_topic, "Odometry or PoseStamped topic -> gt (none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(tf_static_topic, "tf2_msgs/TFMessage static transforms");
    MRPT_SAVE_CONFIG_VAR_COMMENT(lidar_label, "sensorLabel of the scans");
    MRPT_SAVE_CONFIG_VAR_COMMENT(imu_label, "sensorLabel of the IMU samples");
    MRPT_SAVE_CONFIG_VAR_COMMENT(odom_alt_label, "label of the odom_alt poses");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gt_label, "label of the ground-truth poses");
    MRPT_SAVE_CONFIG_VAR_COMMENT(body_frame, "body frame (empty = IMU frame, else LiDAR frame)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(lidar_extrinsic,
                                 "T_body_lidar 'x y z qx qy qz qw' (empty = from tf_static)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gt_child_frame, "child frame of PoseStamped gt (empty = body)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(point_time_field,
                                 "per-point time field: auto (t,time,timestamp,offset_time), none");
    MRPT_SAVE_CONFIG_VAR_COMMENT(point_time_unit, "auto (float: s, integer: ns), s, ms, us, ns");
    MRPT_SAVE_CONFIG_VAR_COMMENT(point_time_reference, "auto, relative (to stamp), absolute");
    MRPT_SAVE_CONFIG_VAR_COMMENT(intensity_max, "intensity stored as 255 in timed scans");
    MRPT_SAVE_CONFIG_VAR_COMMENT(stamp_source,
                                 "auto (record time where header.stamp is 0 / not increasing), "
                                 "header, record");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_clock_offset,
                                 "[s] max LiDAR vs IMU/odom/gt clock offset (0 = no check)");
}

void RosbagParams::validate() const {
    const auto oneOf = [](const std::string& v, std::initializer_list<const char*> allowed) {
        for (const char* a : allowed)
            if (v == a) return true;
        return false;
    };
    if (!oneOf(point_time_unit, {"auto", "s", "ms", "us", "ns"}))
        throw ConfigError("[rosbag] point_time_unit must be auto, s, ms, us or ns, not '" +
                          point_time_unit + "'");
    if (!oneOf(point_time_reference, {"auto", "relative", "absolute"}))
        throw ConfigError("[rosbag] point_time_reference must be auto, relative or absolute, not '" +
                          point_time_reference + "'");
    if (!oneOf(stamp_source, {"auto", "header", "record"}))
        throw ConfigError("[rosbag] stamp_source must be auto, header or record, not '" +
                          stamp_source + "'");
    if (!(max_clock_offset >= 0) || !std::isfinite(max_clock_offset))
        throw ConfigError("[rosbag] max_clock_offset must be >= 0 s (0 = no check)");
    if (!(intensity_max > 0) || !std::isfinite(intensity_max))
        throw ConfigError("[rosbag] intensity_max must be > 0");
    if (point_time_field.empty())
        throw ConfigError("[rosbag] point_time_field must be auto, none or a field name");
    if (!lidar_extrinsic.empty()) {
        std::istringstream ss(lidar_extrinsic);
        double v[7];
        for (double& x : v)
            if (!(ss >> x) || !std::isfinite(x))
                throw ConfigError("[rosbag] lidar_extrinsic must be 'x y z qx qy qz qw', not '" +
                                  lidar_extrinsic + "'");
        std::string extra;
        if (ss >> extra || std::abs(std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]) - 1) > 1e-3)
            throw ConfigError("[rosbag] lidar_extrinsic must be 'x y z qx qy qz qw' with a unit "
                              "quaternion, not '" + lidar_extrinsic + "'");
    }
}

}  // namespace superloc::io
