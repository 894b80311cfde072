// A second, independent odometry (VIO- or wheel-like) with drift, for active fusion.
//
// Poses are T_odom_imu: the body (IMU) frame in the odometry's own frame, which starts at
// identity at the first sample (as a VIO reports its IMU). Relative motions between two samples
// are therefore T_imu(a)_imu(b), what the fusion's relative-pose prior takes. Each increment dT
// between consecutive samples (from ground truth) is corrupted as  dT_noisy = dT * Exp([d_t; d_r])
// with
//   d_t = drift_per_m * |dt| * u  + trans_noise * n_t      (u: fixed unit vector, body frame)
//   d_r = sign * drift_per_rad * dphi + rot_noise * n_r   (dphi: the increment's rotation vector)
// so along a straight path the position error grows by drift_per_m metres per metre travelled
// (u drawn from the seed), and turning about an axis over- or under-estimates the angle
// (sign drawn from the seed) by drift_per_rad radians per radian turned, like a gyro scale error.
// Jumps (off by default): every jump_every seconds the odometry steps by jump_xyz metres along a
// random body direction and jump_deg about a random axis, without saying so in its covariance,
// like a VIO that re-localizes or loses track: wrong on every axis for that one increment,
// including those the LiDAR constrains well.
// drift_axis (default random) fixes u to a body axis: `x` along a corridor is a drift only on the
// axis the scan does not constrain (a wheel-radius scale error), reported in the covariance.
// Heading slip (off by default): every increment also turns about the body z axis by
// slip_deg_per_m degrees per metre travelled (sign from its own stream), not shown in the
// covariance: a wheel odometry whose wheels slip, wrong on yaw, which walls constrain well.
// Wandering error (off by default; doc/sim.md "odom_alt"): a scale error s (a share of each
// increment's translation), a lateral and a vertical drift (metres per metre along body y and z)
// and a heading rate h (yaw per metre) that are random processes over the distance travelled:
// first-order Gauss-Markov (Ornstein-Uhlenbeck in distance) with stationary stds `scale_sigma`,
// `lateral_sigma`, `vertical_sigma`, `heading_sigma_deg` and correlation length `wander_length`
// (0: each drawn once and held for the whole run, an infinite correlation length), and abrupt
// changes: every `change_every_m` metres all four are drawn afresh (a change of floor or tyre
// load). None of it is in the reported covariance, which keeps the fixed drift's bound: like a
// real odometry, it does not know how wrong it is. Drawn from a stream of its own, so the
// fixed drift, noise, jumps and slip are the same numbers with or without it.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/core/types.h>

#include <random>
#include <string>

namespace superloc::sim {

/// Section [odom_alt].
struct OdomAltParams : public mrpt::config::CLoadableOptions {
    bool enabled = true;
    std::string label = "odom_alt";
    double rate_hz = 20.0;        ///< [Hz] 10-30 for VIO/wheel odometry
    double drift_per_m = 0.02;    ///< [m/m] translation drift per metre travelled
    double drift_per_rad = 0.02;  ///< [rad/rad] rotation drift per radian turned
    double trans_noise = 0.0005;  ///< [m] 1-sigma white noise per increment
    double rot_noise_deg = 0.01;  ///< [deg] 1-sigma white noise per increment
    double jump_every = 0;        ///< [s] a jump this often (0 = none)
    double jump_xyz = 0;          ///< [m] size of a jump's translation (random body direction)
    double jump_deg = 0;          ///< [deg] size of a jump's rotation (random axis)
    std::string drift_axis = "random";  ///< body direction of the drift: random | x | y | z
    double slip_deg_per_m = 0;    ///< [deg/m] unreported heading slip about body z (0 = none)
    // Wandering error (0 = off): stationary 1-sigma of each process
    double scale_sigma = 0;        ///< [-] scale error of the translation (a share of each step)
    double lateral_sigma = 0;      ///< [m/m] drift along body y per metre travelled
    double vertical_sigma = 0;     ///< [m/m] drift along body z per metre travelled
    double heading_sigma_deg = 0;  ///< [deg/m] turn about body z per metre travelled
    double wander_length = 0;      ///< [m] correlation length over distance (0: held for the run)
    double change_every_m = 0;     ///< [m] all four drawn afresh this often (0 = never)

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
};

class OdomAltSimulator {
 public:
    OdomAltSimulator(const OdomAltParams& p, uint64_t seed);
    /// Next odometry pose from the true T_map_imu at time t (call in time order).
    PoseStamped step(double t, const SE3d& T_map_imu);

 private:
    OdomAltParams p_;
    std::mt19937_64 rng_;
    std::normal_distribution<double> n01_{0.0, 1.0};
    Vec3d u_;
    double sign_ = 1;
    bool first_ = true;
    SE3d last_gt_, odom_;
    double dist_ = 0, angle_ = 0;
    size_t count_ = 0;
    std::mt19937_64 jump_rng_;  ///< jumps draw from their own stream: the rest is as without them
    double next_jump_ = -1;     ///< [s] time of the next jump (set at the first sample)
    double slip_sign_ = 1;      ///< heading slip's sign (own stream: nothing else changes)
    std::mt19937_64 wander_rng_;  ///< the wandering error's own stream
    Eigen::Vector4d wander_ = Eigen::Vector4d::Zero();  ///< current s, lateral, vertical [m/m], heading [rad/m]
    double next_change_ = 0;        ///< [m] distance of the next abrupt change

 public:
    /// The wandering error's current values: s [-], lateral, vertical [m/m], heading [rad/m].
    const Eigen::Vector4d& wander() const { return wander_; }

 private:
    Eigen::Vector4d wanderSigma() const;
    void drawWander();
};

}  // namespace superloc::sim
