// Private to io: what every bag reader (ROS 1 .bag, ROS 2 .db3, MCAP) hands to the one shared
// bag -> rawlog conversion (bag_import.cpp). A reader lists topics and visits messages in time
// order; a message decodes itself into plain structs that know nothing of ROS, so the three
// formats cannot disagree about what a message means.
#pragma once

#include <superloc/core/types.h>
#include <superloc/io/rosbag.h>

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "../pointcloud2.h"

namespace superloc::io::detail {

/// std_msgs/Header (ROS 1 `seq` is not used).
struct MsgHeader {
    double stamp = 0;  ///< [s] header.stamp: sec + nanosec * 1e-9
    std::string frame_id;
};

/// sensor_msgs/PointCloud2; cloud.data points into the message's bytes (valid during the visit).
struct PointCloud2Msg {
    MsgHeader header;
    PointCloud2View cloud;  ///< cloud.stamp = header.stamp
};

/// sensor_msgs/Imu (orientation and the covariances are not used).
struct ImuMsg {
    MsgHeader header;
    Vec3d angular_velocity = Vec3d::Zero(), linear_acceleration = Vec3d::Zero();
};

/// geometry_msgs/Point + Quaternion as recorded (no normalization here: makePose does it).
struct PoseFields {
    double x = 0, y = 0, z = 0, qx = 0, qy = 0, qz = 0, qw = 1;
};

/// nav_msgs/Odometry (pose part) or geometry_msgs/PoseStamped (no child frame, no covariance).
struct PoseMsg {
    MsgHeader header;
    std::string child_frame_id;
    PoseFields pose;
    std::optional<std::array<double, 36>> covariance;  ///< row-major, ROS order
};

/// One geometry_msgs/TransformStamped of a tf2_msgs/TFMessage.
struct TransformMsg {
    std::string parent, child;
    PoseFields T_parent_child;
};

/// The message types the import understands, by their ROS 1 names (ROS 2 names carry "/msg/").
constexpr const char* kPointCloud2 = "sensor_msgs/PointCloud2";
constexpr const char* kImu = "sensor_msgs/Imu";
constexpr const char* kOdometry = "nav_msgs/Odometry";
constexpr const char* kPoseStamped = "geometry_msgs/PoseStamped";
constexpr const char* kTfMessage = "tf2_msgs/TFMessage";

/// "sensor_msgs/msg/PointCloud2" -> "sensor_msgs/PointCloud2"; ROS 1 names are unchanged.
std::string canonicalType(const std::string& type);

/// One message during a visit. The decoders throw std::runtime_error with a short reason (the
/// caller adds file and topic) when the bytes are not a message of that type.
class BagMessage {
 public:
    virtual ~BagMessage() = default;
    virtual const std::string& topic() const = 0;
    virtual const std::string& type() const = 0;  ///< as the bag names it
    virtual double bagTime() const = 0;           ///< [s] record / receive time
    virtual PointCloud2Msg pointCloud2() const = 0;
    virtual ImuMsg imu() const = 0;
    virtual PoseMsg odometry() const = 0;
    virtual PoseMsg poseStamped() const = 0;
    virtual std::vector<TransformMsg> tfMessage() const = 0;
};

/// A bag being read. Errors are std::runtime_error with one line naming the file.
class BagSource {
 public:
    virtual ~BagSource() = default;
    virtual const std::string& path() const = 0;
    /// Every topic with its type (as the bag names it) and message count, sorted by name.
    virtual std::vector<BagTopic> topics() = 0;
    /// Visits the messages of `topics` in time order (bag time); stops when `fn` returns false.
    virtual void forEach(const std::vector<std::string>& topics,
                         const std::function<bool(const BagMessage&)>& fn) = 0;
};

/// Opens a ROS 1 bag (only in builds with superloc::io_ros1; see open_bag.cpp).
std::unique_ptr<BagSource> openRos1Bag(const std::string& path);
/// Opens a ROS 2 SQLite bag (db3_reader.cpp).
std::unique_ptr<BagSource> openDb3Bag(const std::string& path);
/// Opens an MCAP file (mcap_reader.cpp).
std::unique_ptr<BagSource> openMcapBag(const std::string& path);
/// Opens any of them by content (magic bytes), or a ROS 2 bag folder holding one .db3/.mcap.
std::unique_ptr<BagSource> openBag(const std::string& path);

/// The shared conversion behind importRosbag / listRosbag (bag_import.cpp).
std::vector<BagTopic> listBag(BagSource& bag);
RosbagImportResult importBag(BagSource& bag, const RosbagParams& params,
                             const std::string& out_rawlog, const ProgressFn& progress,
                             const ImportExtras& extras);

}  // namespace superloc::io::detail
