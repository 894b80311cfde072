// IMU preintegration on SO(3) (Forster et al., "IMU Preintegration on Manifold", RSS 2015).
//
// Between two keyframes i and j the IMU samples are summarised by relative increments
// (ΔR_ij, Δv_ij, Δp_ij) expressed in the body frame at i, independent of the states at i and j,
// plus their 9x9 covariance and first-order Jacobians w.r.t. the biases, so that a bias change
// only needs a correction, not a re-integration (Forster eq. 44).
#pragma once

#include <superloc/core/types.h>

#include <vector>

namespace superloc::imu {

using Mat9d = Eigen::Matrix<double, 9, 9>;

/// Accelerometer and gyroscope biases [m/s^2], [rad/s].
struct ImuBias {
    Vec3d acc = Vec3d::Zero();
    Vec3d gyro = Vec3d::Zero();
};

/// Navigation state of the body (IMU) frame in the map frame.
struct NavState {
    Mat3d R = Mat3d::Identity();  ///< R_map_imu
    Vec3d p = Vec3d::Zero();      ///< [m] position of the IMU in map
    Vec3d v = Vec3d::Zero();      ///< [m/s] velocity in map

    SE3d pose() const;
    static NavState fromPose(const SE3d& T_map_imu, const Vec3d& v = Vec3d::Zero());
};

/// Continuous-time noise densities used to propagate the covariance.
struct ImuNoise {
    double acc = 0.02;    ///< [m/s^2/sqrt(Hz)]
    double gyro = 0.002;  ///< [rad/s/sqrt(Hz)]
};

class Preintegration {
   public:
    explicit Preintegration(const ImuBias& bias_lin = {}, const ImuNoise& noise = {});

    /// Restarts from identity increments with a new linearisation bias.
    void reset(const ImuBias& bias_lin);

    /// Adds one measurement held constant over dt [s] (Forster eqs. 26, 59-63).
    void integrate(const Vec3d& acc, const Vec3d& gyro, double dt);

    double dt() const { return dt_; }
    const ImuBias& biasLin() const { return bias_lin_; }
    const Mat3d& deltaR() const { return dR_; }
    const Vec3d& deltaV() const { return dv_; }
    const Vec3d& deltaP() const { return dp_; }
    /// Covariance of the (rotation, velocity, position) increment errors, in that order.
    const Mat9d& covariance() const { return cov_; }
    const Mat3d& dR_dbg() const { return dR_dbg_; }
    const Mat3d& dv_dba() const { return dv_dba_; }
    const Mat3d& dv_dbg() const { return dv_dbg_; }
    const Mat3d& dp_dba() const { return dp_dba_; }
    const Mat3d& dp_dbg() const { return dp_dbg_; }

    /// Increments corrected to first order for another bias (Forster eq. 44).
    Mat3d correctedDeltaR(const ImuBias& b) const;
    Vec3d correctedDeltaV(const ImuBias& b) const;
    Vec3d correctedDeltaP(const ImuBias& b) const;

    /// The same increments with the covariance of noise densities `s` times these (cov s^2).
    Preintegration withNoiseScale(double s) const {
        Preintegration p = *this;
        p.cov_ *= s * s;
        p.noise_.acc *= s;
        p.noise_.gyro *= s;
        return p;
    }

    /// State at j from the state at i (Forster eq. 33), gravity g_map e.g. (0, 0, -9.81).
    NavState predict(const NavState& i, const ImuBias& b, const Vec3d& g_map) const;

   private:
    ImuBias bias_lin_;
    ImuNoise noise_;
    double dt_ = 0;
    Mat3d dR_ = Mat3d::Identity();
    Vec3d dv_ = Vec3d::Zero(), dp_ = Vec3d::Zero();
    Mat3d dR_dbg_ = Mat3d::Zero(), dv_dba_ = Mat3d::Zero(), dv_dbg_ = Mat3d::Zero();
    Mat3d dp_dba_ = Mat3d::Zero(), dp_dbg_ = Mat3d::Zero();
    Mat9d cov_ = Mat9d::Zero();
};

/// True when a time-sorted buffer covers [t0, t1] densely enough to integrate: a sample at or
/// before t0 + max_gap, one at or after t1 - max_gap, and no two consecutive samples in between
/// farther apart than max_gap. integrateInterval() holds each sample until the next one, so a
/// hole in the data (an IMU dropout) would otherwise be bridged by one stale sample.
bool coversInterval(const std::vector<ImuSample>& samples, double t0, double t1, double max_gap);

/// Integrates the samples of a time-sorted buffer over [t0, t1] into `pre` (which is not reset).
/// Each sample is held from its time to the next one; the interval ends are cut exactly, and a
/// first sample later than t0 is extended back to t0. Returns how many samples contributed
/// (0: no sample covers the interval, nothing integrated).
size_t integrateInterval(
    const std::vector<ImuSample>& samples, double t0, double t1, Preintegration& pre);

/// The IMU's poses at `times` (increasing) predicted from `start`, the state at t0, by integrating
/// the samples over [t0, τ] (Preintegration::predict, bias `b`), so that the pose at the last
/// integrated time equals the frame's own prediction. A time at or before t0 gets `start`
/// moved back at its velocity. For per-point deskew along the IMU's trajectory.
std::vector<SE3d> predictPoses(const std::vector<ImuSample>& samples, double t0, const NavState& start,
                               const ImuBias& b, const Vec3d& g_map, const std::vector<double>& times);

/// A sensor's motion over one sweep [t_scan + s_min, t_scan] (s_min < 0) along the IMU's predicted
/// trajectory (predictPoses from `start` at t0): at n + 1 relative times s from s_min to 0, the
/// pose of the sensor (mounted at T_imu_sensor) at t_scan + s expressed in its own frame at
/// t_scan. For per-point deskew (features::SweepMotion::fromSamples).
struct SweepPoses {
    std::vector<double> s;
    std::vector<SE3d> T_end_s;
};
SweepPoses sweepPoses(const std::vector<ImuSample>& samples, double t0, const NavState& start, const ImuBias& b,
                      const Vec3d& g_map, double t_scan, double s_min, const SE3d& T_imu_sensor, int n = 16);

}  // namespace superloc::imu
