// Plain data types shared by every SuperLoc module.
//
// Frame convention (doc/design.md#3-data-conventions): T_a_b maps points from frame b into frame a. World/map frame
// `map`, sensor frame `lidar`, body = IMU frame `imu`. Times are seconds (double), the same
// clock as the rawlog's observation timestamps.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace superloc {

using Vec3f = Eigen::Vector3f;
using Vec3d = Eigen::Vector3d;
using Mat3d = Eigen::Matrix3d;
using Mat6d = Eigen::Matrix<double, 6, 6>;
using Vec6d = Eigen::Matrix<double, 6, 1>;
using SE3d = Eigen::Isometry3d;

/// One LiDAR sweep in the sensor frame.
struct Scan {
    double t = 0;  ///< [s] the time the points are referred to (end of sweep) and the pose refers to
    std::vector<Vec3f> points;    ///< [m] lidar frame, firing order when known
    std::vector<float> intensity; ///< same size as points, or empty
    /// [s] per-point time relative to `t` (<= 0 for a sweep ending at t), or empty when unknown
    std::vector<float> rel_time;
    SE3d T_imu_lidar = SE3d::Identity();  ///< extrinsic: the observation's sensorPose
    std::string label;                    ///< sensor label of the observation

    size_t size() const { return points.size(); }
    bool empty() const { return points.empty(); }
};

/// One IMU sample in the IMU (body) frame.
struct ImuSample {
    double t = 0;                 ///< [s]
    Vec3d acc = Vec3d::Zero();    ///< [m/s^2] specific force (includes -gravity), body frame
    Vec3d gyro = Vec3d::Zero();   ///< [rad/s] angular rate, body frame
};

/// A timestamped 6-DoF pose, e.g. a trajectory sample, a `gt` or an `odom_alt` observation.
struct PoseStamped {
    double t = 0;                  ///< [s]
    SE3d pose = SE3d::Identity();  ///< T_frame_body; for a trajectory T_map_lidar
    /// 6x6 covariance in (x y z roll pitch yaw) order, when the source gave one
    std::optional<Mat6d> cov;
};

using Trajectory = std::vector<PoseStamped>;

/// A point cloud as stored in map files: points plus optional per-point attributes.
struct PointCloud {
    std::vector<Vec3f> points;
    std::vector<float> intensity;              ///< empty or same size as points
    std::vector<Vec3f> normals;                ///< empty or same size as points
    std::vector<std::array<uint8_t, 3>> rgb;   ///< empty or same size as points

    size_t size() const { return points.size(); }
    bool empty() const { return points.empty(); }
};

/// Names of the six motion directions, in the order used by every 6-vector of SuperLoc
/// (translation first): x, y, z, roll, pitch, yaw.
inline constexpr const char* kAxisNames[6] = {"x", "y", "z", "roll", "pitch", "yaw"};

}  // namespace superloc
