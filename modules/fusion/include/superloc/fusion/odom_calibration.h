// Online calibration of odom_alt's systematic error against the LiDAR (active fusion,
// doc/method.md §2). Wheel odometry and VIO err mostly systematically: a scale error, a drift
// direction, a heading that slips with distance. Such an error is a function of the motion, so
// it can be learned on the frames where the scan holds an axis and removed where it does not:
//
//   translation, body axis k:  t_odom,k = t_k + b_k d                     (d = distance over the frame)
//   rotation,    body axis k:  phi_odom,k = (1 + s_k) phi_k + c_k d       (scale; rotation per metre)
//
// b (per-metre drift, 3), s (rotation scale, 3) and c (per-metre rotation, 3) are fitted by
// least squares, forgetting with the distance travelled, on the axes the scan held in that frame
// (the estimate there is the scan's, not odom_alt's or the IMU chain's). What is left after the
// correction gives odom_alt's per-frame standard deviation per axis, with the fit's own
// uncertainty growing with d: the weight odom_alt is worth on an axis the scan does not hold.
// A frame whose residual on a held axis is far outside that (a jump) is not learned from and
// counts as an outlier; many in a row mean the error itself changed, and that axis starts again.
#pragma once

#include <superloc/core/types.h>

#include <array>
#include <optional>

namespace superloc::fusion {

struct OdomCalibrationParams {
    double memory_m = 500.0;      ///< [m] forgetting distance of the fit (exponential)
    double min_held_m = 10.0;     ///< [m] travel on held frames before an axis's fit is used
    double outlier_sigmas = 5.0;  ///< [-] residual beyond this many stds: not learned from
    /// this many outliers in a row on an axis: its error changed (not a jump), the fit restarts
    int restart_after = 10;
    double sigma_floor_xyz = 0.0005;  ///< [m] per-frame std never below this
    double sigma_floor_rot = 0.01 * 3.14159265358979323846 / 180.0;  ///< [rad] likewise
};

class OdomCalibration {
   public:
    explicit OdomCalibration(const OdomCalibrationParams& p = {}) : p_(p) {}

    /// Learns from one frame: odom_alt's body motion `odom` against the estimate's `est`
    /// (T_prev^-1 T_cur, both over the same scan times), on the axes `held` (x y z roll pitch yaw)
    /// where the scan constrained the estimate. Returns the axes whose residual was an outlier.
    std::array<bool, 6> update(const SE3d& odom, const SE3d& est, const std::array<bool, 6>& held);

    /// odom_alt's motion with the fitted systematic error removed (axes without a usable fit
    /// are left as they are).
    SE3d correct(const SE3d& odom) const;

    /// Per-frame std of the corrected motion per axis, for a frame of odom_alt motion `odom`;
    /// empty entries (NaN) where the axis has no usable fit yet.
    Vec6d sigma(const SE3d& odom) const;

    /// Whether axis k has been fitted over at least min_held_m of held travel.
    bool calibrated(int k) const;

    Vec3d drift() const;         ///< b [m/m]
    Vec3d rotationScale() const; ///< s [-]
    Vec3d rotationPerM() const;  ///< c [rad/m]
    const std::array<int, 6>& outliers() const { return outliers_; }
    const std::array<int, 6>& restarts() const { return restarts_; }

   private:
    /// Sufficient statistics of one axis's weighted least squares r = a^T x, x = (slope on the
    /// motion, slope on d) for rotation, x = (b) for translation (second entry unused).
    struct Axis {
        Eigen::Matrix2d A = Eigen::Matrix2d::Zero();  ///< sum a a^T
        Eigen::Vector2d g = Eigen::Vector2d::Zero();  ///< sum a r
        double rr = 0;        ///< sum r^2
        double n = 0;         ///< frames (forgotten like the rest)
        double held_m = 0;    ///< held travel (not forgotten)
        int outlier_run = 0;  ///< outliers in a row
        double var = 0;       ///< residual variance per frame after the correction
        Eigen::Vector2d x = Eigen::Vector2d::Zero();
        Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();  ///< of x, per unit variance
    };
    void solve(Axis& a, bool rotation) const;

    OdomCalibrationParams p_;
    std::array<Axis, 6> axes_;
    std::array<int, 6> outliers_{};
    std::array<int, 6> restarts_{};
};

}  // namespace superloc::fusion
