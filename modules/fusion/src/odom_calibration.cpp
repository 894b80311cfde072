#include <superloc/core/se3.h>
#include <superloc/fusion/odom_calibration.h>

#include <cmath>
#include <limits>

namespace superloc::fusion {

namespace {
/// Ridge on the fit (in the units of sum a a^T): a weak pull of b, s, c towards zero that keeps
/// an axis defined before it has seen motion (a straight drive says nothing of a rotation scale).
constexpr double kRidgeSlope = 1e-3;   ///< on the motion term: b [m^2], s [rad^2]
constexpr double kRidgePerM = 1e-1;    ///< on the per-metre rotation term c [m^2]


Eigen::Vector2d regressor(int k, double d, double motion_k) {
    return k < 3 ? Eigen::Vector2d(d, 0.0) : Eigen::Vector2d(motion_k, d);
}
}  // namespace

void OdomCalibration::solve(Axis& a, bool rotation) const {
    Eigen::Matrix2d A = a.A;
    A(0, 0) += rotation ? kRidgeSlope : kRidgeSlope;
    A(1, 1) += rotation ? kRidgePerM : 1.0;  // translation: the second entry is unused
    const Eigen::LDLT<Eigen::Matrix2d> ldlt(A);
    a.x = ldlt.solve(a.g);
    if (!rotation) a.x[1] = 0;
    a.cov = ldlt.solve(Eigen::Matrix2d::Identity());
    const double ssr = std::max(0.0, a.rr - 2.0 * a.x.dot(a.g) + a.x.dot(a.A * a.x));
    const double dof = a.n - (rotation ? 2.0 : 1.0);
    a.var = dof > 1.0 ? ssr / dof : 0.0;
}

std::array<bool, 6> OdomCalibration::update(const SE3d& odom, const SE3d& est, const std::array<bool, 6>& held) {
    std::array<bool, 6> outlier{};
    const double d = odom.translation().norm();
    if (!std::isfinite(d)) return outlier;
    const Vec3d phi_o = logSO3(odom.linear()), phi_e = logSO3(est.linear());
    const Vec3d t_o = odom.translation(), t_e = est.translation();
    const double forget = std::exp(-d / p_.memory_m);
    for (int k = 0; k < 6; ++k) {
        if (!held[k]) continue;
        Axis& a = axes_[k];
        const bool rot = k >= 3;
        const double r = rot ? phi_o[k - 3] - phi_e[k - 3] : t_o[k] - t_e[k];
        const Eigen::Vector2d reg = regressor(k, d, rot ? phi_e[k - 3] : 0.0);
        if (!std::isfinite(r)) continue;
        // A residual far outside what the fit leaves (a jump, a slip it has not seen) is not
        // learned from; tested once the fit has a variance (a few frames).
        if (a.n >= 5 && a.var > 0) {
            const double floor = rot ? p_.sigma_floor_rot : p_.sigma_floor_xyz;
            const double s = std::max(floor, std::sqrt(a.var * (1.0 + reg.dot(a.cov * reg))));
            if (std::abs(r - reg.dot(a.x)) > p_.outlier_sigmas * s) {
                outlier[k] = true;
                ++outliers_[k];
                if (++a.outlier_run < p_.restart_after) continue;
                a = Axis{};  // the error changed: learn it again, from this frame
                ++restarts_[k];
            }
        }
        a.outlier_run = 0;
        a.A = forget * a.A + reg * reg.transpose();
        a.g = forget * a.g + reg * r;
        a.rr = forget * a.rr + r * r;
        a.n = forget * a.n + 1.0;
        a.held_m += d;
        solve(a, rot);
    }
    return outlier;
}

bool OdomCalibration::calibrated(int k) const { return axes_[k].held_m >= p_.min_held_m && axes_[k].n >= 5; }

SE3d OdomCalibration::correct(const SE3d& odom) const {
    const double d = odom.translation().norm();
    Vec3d t = odom.translation(), phi = logSO3(odom.linear());
    for (int k = 0; k < 3; ++k)
        if (calibrated(k)) t[k] -= axes_[k].x[0] * d;
    for (int k = 0; k < 3; ++k)
        if (calibrated(3 + k)) {
            const auto& x = axes_[3 + k].x;
            phi[k] = (phi[k] - x[1] * d) / std::max(0.1, 1.0 + x[0]);
        }
    SE3d out = SE3d::Identity();
    out.linear() = expSO3(phi);
    out.translation() = t;
    return out;
}

Vec6d OdomCalibration::sigma(const SE3d& odom) const {
    const double d = odom.translation().norm();
    const Vec3d phi = logSO3(odom.linear());
    Vec6d s;
    for (int k = 0; k < 6; ++k) {
        if (!calibrated(k)) {
            s[k] = std::numeric_limits<double>::quiet_NaN();
            continue;
        }
        const Axis& a = axes_[k];
        const Eigen::Vector2d reg = regressor(k, d, k >= 3 ? phi[k - 3] : 0.0);
        const double floor = k >= 3 ? p_.sigma_floor_rot : p_.sigma_floor_xyz;
        s[k] = std::max(floor, std::sqrt(a.var * (1.0 + reg.dot(a.cov * reg))));
    }
    return s;
}

Vec3d OdomCalibration::drift() const { return {axes_[0].x[0], axes_[1].x[0], axes_[2].x[0]}; }
Vec3d OdomCalibration::rotationScale() const { return {axes_[3].x[0], axes_[4].x[0], axes_[5].x[0]}; }
Vec3d OdomCalibration::rotationPerM() const { return {axes_[3].x[1], axes_[4].x[1], axes_[5].x[1]}; }

}  // namespace superloc::fusion
