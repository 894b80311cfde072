// Smooth (C2) platform trajectories with analytic derivatives, so the IMU is exact.
//
// Position and Euler angles (roll, pitch, yaw; R = Rz(yaw) Ry(pitch) Rx(roll)) are uniform cubic
// B-splines over knots sampled from a DensePath, plus a platform "gait": sinusoidal bobbing and
// sway faded in with a quintic ramp. All are C2, so acceleration and angular rate are continuous.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/core/types.h>
#include <superloc/sim/path.h>

#include <vector>

namespace superloc::sim {

/// Section [trajectory]: the platform's motion (car, handheld, legged...).
struct TrajectoryParams : public mrpt::config::CLoadableOptions {
    std::string platform = "car";    ///< free text, for the docs (car, handheld, legged, wheeled)
    double max_speed = 5.0;          ///< [m/s]
    double max_yaw_rate_deg = 57.0;  ///< [deg/s]
    double max_accel = 2.0;          ///< [m/s^2]
    double max_lat_accel = 5.0;      ///< [m/s^2]
    double corner_radius = 4.0;      ///< [m] fillet radius at waypoint corners
    double body_height = 0.5;        ///< [m] IMU (body) height above the floor it moves on
    double knot_dt = 0.2;            ///< [s] B-spline knot spacing (smoothing time scale)
    double pitch_follow = 1.0;       ///< [0..1] how much the body pitches with the path slope
    double bob_amplitude = 0.0;      ///< [m] vertical gait bobbing amplitude
    double bob_frequency = 2.0;      ///< [Hz]
    double sway_roll_deg = 0.0;      ///< [deg] roll sway amplitude
    double sway_pitch_deg = 0.0;     ///< [deg] pitch sway amplitude
    double sway_yaw_deg = 0.0;       ///< [deg] yaw sway amplitude
    double sway_frequency = 1.0;     ///< [Hz] (pitch sways at 2x, yaw at 0.5x this)
    double ramp_time = 2.0;          ///< [s] gait fade-in after the start (starts at rest)

    MotionLimits limits() const;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
};

/// Kinematic state of the body (IMU) frame at one instant, map frame.
struct BodyState {
    double t = 0;
    SE3d T_map_body = SE3d::Identity();
    Vec3d vel = Vec3d::Zero();         ///< [m/s] map frame
    Vec3d acc = Vec3d::Zero();         ///< [m/s^2] map frame (kinematic, without gravity)
    Vec3d omega_body = Vec3d::Zero();  ///< [rad/s] angular rate in the body frame
};

class SmoothTrajectory {
 public:
    /// Knots every p.knot_dt along the path, starting at time t0 at rest; the trajectory lasts
    /// min(path.duration(), max_duration).
    SmoothTrajectory(const DensePath& path, const TrajectoryParams& p, double t0,
                     double max_duration);

    double startTime() const { return t0_; }
    double endTime() const { return t_end_; }
    /// endTime() - startTime(), exact (not rounded at the absolute time's resolution).
    double duration() const { return duration_; }
    /// Pose and derivatives at time t (clamped to [startTime, endTime]).
    BodyState at(double t) const;
    /// Pose only (same as at(t).T_map_body).
    SE3d pose(double t) const { return at(t).T_map_body; }

 private:
    struct Eval {
        Vec3d x, dx, ddx;
    };
    Eval spline(const std::vector<Vec3d>& ctrl, double t) const;

    TrajectoryParams p_;
    double t0_ = 0, t_end_ = 0, duration_ = 0, dt_ = 0.2;
    std::vector<Vec3d> pos_ctrl_, rpy_ctrl_;
};

}  // namespace superloc::sim
