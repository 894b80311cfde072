// Step 1 of a frame (doc/localizer.md): where the body is at the scan's time, and how it moved
// over the sweep (for deskew). With IMU samples covering the interval since the last frame:
// Forster preintegration from the last state; without: odom_alt's motion where the method's
// fusion policy predicts from it (OdomFusion::motion), else constant velocity from the last two.
// The first frame starts at its initial pose, with the gyro bias when the IMU is at rest.
#pragma once

#include <superloc/fusion/state.h>
#include <superloc/imu/imu_params.h>
#include <superloc/imu/preintegration.h>
#include <superloc/localization/method_variant.h>
#include <superloc/localization/sensor_history.h>

#include <optional>

namespace superloc::localization {

struct Prediction {
    SE3d T_map_imu = SE3d::Identity();
    Vec3d v = Vec3d::Zero();
    Vec3d w_body = Vec3d::Zero();  ///< [rad/s] angular rate for deskew
    Vec3d v_body = Vec3d::Zero();  ///< [m/s] body-frame velocity for deskew
    bool used_imu = false;         ///< pose predicted by IMU preintegration (`pre` holds it)
    bool twist_from_imu = false;   ///< deskew twist measured by the IMU
    bool at_rest = false;          ///< first frame: the IMU says the robot is at rest (velocity 0)
    bool from_odom = false;        ///< no IMU: predicted by odom_alt's motion (OdomFusion::motion)
    /// A hypothesis placed away from the last pose (Tracker::solveFrom): its velocity is this body
    /// velocity turned with its pose, not the difference from the last pose
    std::optional<Vec3d> keep_v_body;
};

/// A frame after the first, at time t, from the last state `prev` (and the one before it, for
/// the constant-velocity model); `policy`: the method's odom_alt fusion. `pre` receives the IMU
/// preintegration when it is used.
Prediction predictMotion(const fusion::FrameState& prev, const std::optional<fusion::FrameState>& prev_prev, double t,
                         const SensorHistory& sensors, const OdomFusion& policy, bool use_imu, const Vec3d& g_map,
                         imu::Preintegration& pre);

/// The first frame, at `T_map_imu` (its initial pose): the IMU at rest over its first
/// init_window gives the gyro bias (`bias`, and `tilt_deg`: its gravity against the initial
/// attitude); the sweep's rotation comes from the gyro alone (the velocity is not known yet).
Prediction predictFirst(const Scan& scan, const SE3d& T_map_imu, const SensorHistory& sensors, bool use_imu,
                        const imu::ImuParams& imu, imu::ImuBias& bias, std::optional<double>& tilt_deg);

}  // namespace superloc::localization
