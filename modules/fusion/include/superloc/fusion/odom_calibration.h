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
//
// What the corrected odom_alt is worth is measured out of sample (doc/method.md §2, "What
// odom_alt is worth"): on the held frames, blocks of held travel of several lengths H (2.5 m to
// 160 m) are corrected with the fit as it stood when each block began, and the squared sum of
// what the correction then left is the error the calibration makes when it is carried H metres
// without a check. V(D) = a D + b D^2 is fitted to those (a: an error that averages out, b: one
// that keeps its sign, a drift the fit did not remove), and a frame of d metres at D metres since
// the scan last held the axis gets the per-frame variance V(D + d) - V(D): summed over the
// frames of a blind stretch, the fused odometry is as sure as it has shown it can be over that
// stretch, and no surer. A wandering or changed error shows in the longer blocks at once; a
// fixed one, once fitted, leaves small errors at every length.
//
// How much of the correction to apply is measured the same way: per block length, the share k
// of the correction that best predicted the raw error out of sample (sum(e c) / sum(c^2) over the
// blocks, clamped to [0, 1], with one pseudo-block where the correction was right). A fixed
// error keeps k ~ 1; a correction learned from an error that has since wandered (a fit restarted
// on a recent stretch) is applied only in part, at D metres since the check the share of the
// blocks of 2 D, and V(D) is fitted to what the shrunk correction left. Beyond the longest block
// measured the share falls as H / 2D towards c^2 / (c^2 + wb): the fitted correction c is the
// fixed error plus the mean of what wandered while it was fitted, and wb (the error the blocks
// show keeping its sign) says how large that wandering part is.
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
    /// Out-of-sample blocks of held travel [m], ascending (kHorizons of them).
    std::array<double, 7> horizons{2.5, 5.0, 10.0, 20.0, 40.0, 80.0, 160.0};
    int min_blocks = 3;  ///< [-] blocks of a length before it counts in the worth's fit
    /// false: nothing is corrected (correct() returns odom_alt's motion as it is) and the blocks
    /// measure the raw motion's error: what the uncalibrated odom_alt is worth, the pose
    /// covariance of the methods that fuse it raw (passive, superloc_paper; doc/method.md §4).
    bool apply_correction = true;
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

    /// The share [0, 1] of the fitted correction applied on each axis now (its distance since
    /// held); 1 where not measured yet.
    Vec6d shrink() const;

    /// Per-frame std of the corrected motion per axis, for a frame of odom_alt motion `odom`
    /// taken at the distance since the scan last held each axis (out of sample, above); NaN
    /// where the axis has no fit, or no measured worth, yet.
    /// `worth` (if not null) receives what the corrected motion is worth for the pose's
    /// covariance: the same, except beyond the longest block length the worth has measured (H),
    /// where nothing has shown how the error grows. There V(D) continues as V(H) (D / H)^3, the
    /// growth of an error whose rate itself wanders (a random walk of the drift; a wandering
    /// scale over less than its correlation length), which bounds any slower one; the solve
    /// keeps the returned std (doc/method.md §2, "What it is worth beyond the longest block").
    Vec6d sigma(const SE3d& odom, Vec6d* worth = nullptr) const;
    /// [m] per axis: the longest block length with at least min_blocks blocks; 0 where none.
    Vec6d measuredHorizon() const;
    /// The in-sample std (the fit's own residual, as before the out-of-sample worth), NaN where
    /// not calibrated: for comparison (tests, doc/method.md).
    Vec6d fitSigma(const SE3d& odom) const;
    /// The worth's model per axis: V(D) = a D + b D^2 [m^2 or rad^2]; NaN where not measured.
    Vec6d worthA() const;
    Vec6d worthB() const;
    /// [m] travel since the scan last held each axis.
    Vec6d sinceHeld() const;

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
        // Out-of-sample worth (above): per block length, the open block and the forgotten
        // sums of the closed ones (squared error, length, count).
        struct Block {
            bool open = false;
            Eigen::Vector2d x0 = Eigen::Vector2d::Zero();  ///< the correction when it began
            double S = 0, C = 0, L = 0;  ///< raw error, the correction's prediction, held travel
        };
        std::array<Block, 7> blocks;
        /// Per block length, forgotten sums over the closed blocks: raw error squared, raw error
        /// times the correction's prediction, prediction squared; held travel; count.
        std::array<double, 7> ee{}, ec{}, cc{}, len{}, cnt{};
        std::array<double, 7> shrink{1, 1, 1, 1, 1, 1, 1};  ///< the correction's share per block length, [0, 1]
        double wa = 0, wb = 0;  ///< V(D) = wa D + wb D^2
        bool worth = false;
        double since_m = 0;     ///< travel since the scan last held the axis (not reset by a restart)
    };
    void solve(Axis& a, bool rotation) const;
    void fitWorth(Axis& a) const;
    /// The share of the fitted correction applied at `D` metres since the axis was held.
    double shrinkAt(const Axis& a, double D) const;


    OdomCalibrationParams p_;
    std::array<Axis, 6> axes_;
    std::array<int, 6> outliers_{};
    std::array<int, 6> restarts_{};
};

}  // namespace superloc::fusion
