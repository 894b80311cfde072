// ROS 1 bags (sensor_msgs/PointCloud2, sensor_msgs/Imu, nav_msgs/Odometry,
// geometry_msgs/PoseStamped, tf2_msgs/TFMessage on /tf_static) -> rawlog. Library
// superloc::io_ros1 (built when Debian's librosbag-storage-dev and the message headers are
// installed); doc/your-data.md shows it in use.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/io/importers.h>

#include <string>
#include <vector>

namespace superloc::io {

/// Which bag topic becomes which rawlog observation, frames and per-point time; section
/// [rosbag] of the INI. Topics: empty = automatic (the bag's only topic of that type, none if
/// it has none), `none` = not imported; a named topic must exist and have a supported type.
struct RosbagParams : public mrpt::config::CLoadableOptions {
    std::string lidar_topic;     ///< sensor_msgs/PointCloud2 -> LiDAR scans (empty = auto)
    std::string imu_topic;       ///< sensor_msgs/Imu -> CObservationIMU (empty = auto)
    std::string odom_alt_topic = "none";  ///< nav_msgs/Odometry -> `odom_alt` pose + covariance
    std::string gt_topic = "none";  ///< nav_msgs/Odometry or geometry_msgs/PoseStamped -> `gt`
    std::string tf_static_topic = "/tf_static";  ///< tf2_msgs/TFMessage static transforms
    std::string lidar_label = "lidar";  ///< sensorLabel of the scans
    std::string imu_label = "imu";      ///< sensorLabel of the IMU samples
    std::string odom_alt_label = "odom_alt";  ///< label of the odom_alt poses
    std::string gt_label = "gt";              ///< label of the ground-truth poses
    /// Body frame (the rawlog's `imu` frame; scans get sensorPose = T_body_lidar). Empty = the
    /// IMU messages' frame_id when an IMU topic is imported, else the LiDAR's own frame.
    std::string body_frame;
    /// T_body_lidar as "x y z qx qy qz qw"; empty = looked up in the static transforms.
    std::string lidar_extrinsic;
    /// Child frame of geometry_msgs/PoseStamped ground truth (empty = body frame); Odometry
    /// messages name theirs (child_frame_id).
    std::string gt_child_frame;
    /// Per-point time field: auto (first of t, time, timestamp, offset_time), none, or a name
    std::string point_time_field = "auto";
    std::string point_time_unit = "auto";       ///< auto (float: s, integer: ns), s, ms, us, ns
    std::string point_time_reference = "auto";  ///< auto, relative (to header.stamp), absolute
    /// Intensity that maps to 255 in timed scans (their carrier stores a byte; doc/io.md)
    double intensity_max = 255.0;
    /// The time of each message: header (header.stamp), record (the bag's record / receive
    /// time) or auto (per topic: the record time when header.stamp is 0 on any message or does
    /// not increase on more than 1% of them, else header.stamp). doc/your-data.md, section 2.
    std::string stamp_source = "auto";
    /// [s] The LiDAR's clock and each other imported topic's (IMU, odom_alt, gt) must overlap
    /// and lie within this of each other, measured against the bag's record time; 0 = no check.
    double max_clock_offset = 1.0;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
};

/// One topic of a bag.
struct BagTopic {
    std::string topic, type;
    size_t messages = 0;
};

/// How one imported topic was stamped ([rosbag] stamp_source).
struct TopicStamps {
    std::string topic;
    bool record_time = false;  ///< stamped with the bag's record time, else with header.stamp
    std::string reason;        ///< why stamp_source = auto chose the record time ("" if it did not)
};

/// What importRosbag() did, beyond ImportResult.
struct RosbagImportResult : ImportResult {
    size_t timed_scans = 0;         ///< scans written with per-point time
    std::string lidar_topic, imu_topic;  ///< the topics used ("" = none)
    std::string time_field;         ///< per-point time field of the first timed scan
    /// Messages skipped because their stamp (TopicStamps) did not increase on their topic
    std::vector<std::pair<std::string, size_t>> non_monotonic;
    /// The clock of every imported topic (LiDAR, IMU, odom_alt, gt, those imported)
    std::vector<TopicStamps> stamps;
};

/// The topics of a bag, sorted by name. Throws std::runtime_error "<bag>: <reason>".
std::vector<BagTopic> listRosbag(const std::string& bag);

/// Imports a ROS 1 or ROS 2 bag into an observations-only rawlog (doc/io.md). Times are the
/// messages' header.stamp or the bag's record time ([rosbag] stamp_source; which one per topic in
/// RosbagImportResult::stamps). Throws std::runtime_error with one line naming the bag (and
/// topic) on a missing, truncated or unreadable bag, a missing or wrongly typed topic, a
/// PointCloud2 without x/y/z, an unresolvable extrinsic (including an empty frame_id where a
/// transform is needed), or LiDAR and IMU / odom_alt / gt clocks that do not agree ([rosbag]
/// max_clock_offset); the clock check and the LiDAR/IMU frames come before anything is
/// written. A message whose stamp does not increase on its topic is skipped and counted
/// (RosbagImportResult::non_monotonic).
RosbagImportResult importRosbag(const std::string& bag, const RosbagParams& params,
                                const std::string& out_rawlog, const ProgressFn& progress = {},
                                const ImportExtras& extras = {});

}  // namespace superloc::io
