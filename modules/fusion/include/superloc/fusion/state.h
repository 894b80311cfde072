// One frame's optimisation state, laid out as Ceres parameter blocks.
#pragma once

#include <superloc/core/types.h>
#include <superloc/imu/preintegration.h>

namespace superloc::fusion {

/// pose = T_map_imu as [tx ty tz qx qy qz qw] (Eigen quaternion order; see PoseManifold);
/// speed_bias = [v (map, m/s), acc bias (m/s^2), gyro bias (rad/s)].
struct FrameState {
    double t = 0;  ///< [s]
    double pose[7] = {0, 0, 0, 0, 0, 0, 1};
    double speed_bias[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};

    SE3d T_map_imu() const;
    void setPose(const SE3d& T_map_imu);
    Vec3d velocity() const { return Vec3d(speed_bias[0], speed_bias[1], speed_bias[2]); }
    void setVelocity(const Vec3d& v);
    imu::ImuBias bias() const;
    void setBias(const imu::ImuBias& b);
    imu::NavState nav() const { return imu::NavState::fromPose(T_map_imu(), velocity()); }
};

}  // namespace superloc::fusion
