// SensorHistory: the IMU and odom_alt between scans (sensor_history.h).
#include <superloc/core/se3.h>
#include <superloc/localization/sensor_history.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace superloc::localization {

void SensorHistory::addImu(const ImuSample& s) {
    if (!imu_.empty() && s.t <= imu_.back().t) return;  // duplicates / out of order: ignored
    imu_.push_back(s);
}

void SensorHistory::addOdomAlt(const PoseStamped& p) {
    if (!odom_alt_.empty() && p.t <= odom_alt_.back().t) return;
    odom_alt_.push_back(p);
}

std::optional<SE3d> SensorHistory::odomAltDelta(double t0, double t1) const {
    const auto a = interpolateAt(odom_alt_, t0, 0.5, 1e-3);
    const auto b = interpolateAt(odom_alt_, t1, 0.5, 1e-3);
    if (!a || !b) return std::nullopt;
    return orthonormalize(a->inverse() * *b);
}

std::optional<Mat6d> SensorHistory::odomAltCovAt(double t) const {
    // Linear interpolation of the reported covariance between the samples around t.
    const auto it = std::lower_bound(odom_alt_.begin(), odom_alt_.end(), t,
                                     [](const PoseStamped& p, double tt) { return p.t < tt; });
    if (it == odom_alt_.end() || !it->cov) return std::nullopt;
    if (it == odom_alt_.begin() || it->t == t) return it->cov;
    const auto prev = std::prev(it);
    if (!prev->cov || !(it->t > prev->t)) return it->cov;
    const double f = (t - prev->t) / (it->t - prev->t);
    return Mat6d((1 - f) * *prev->cov + f * *it->cov);
}

std::optional<Mat3d> SensorHistory::gravityAt(double t, double gravity) const {
    // The mean specific force over the last half second is -gravity in the IMU frame, up to the
    // platform's own mean acceleration (a walker: a few tenths of m/s^2, ~1-2 deg).
    Vec3d f = Vec3d::Zero();
    int n = 0;
    for (auto it = imu_.rbegin(); it != imu_.rend() && it->t >= t - 0.5; ++it)
        if (it->t <= t + 0.05) f += it->acc, ++n;
    if (n < 10 || !(f.norm() > 0)) return std::nullopt;
    f /= n;
    const double g = f.norm();
    if (std::abs(g - gravity) > 0.2 * gravity) return std::nullopt;  // not gravity-dominated
    // R_level_imu: the rotation (no yaw) taking the measured up direction onto the map's z.
    return Mat3d(Eigen::Quaterniond::FromTwoVectors(f / g, Vec3d::UnitZ()).toRotationMatrix());
}

void SensorHistory::forgetBefore(double t) {
    const auto keep = std::lower_bound(imu_.begin(), imu_.end(), t - 1.0,
                                       [](const ImuSample& s, double tt) { return s.t < tt; });
    imu_.erase(imu_.begin(), keep);
    const auto keep_odom = std::lower_bound(odom_alt_.begin(), odom_alt_.end(), t - 2.0,
                                            [](const PoseStamped& p, double tt) { return p.t < tt; });
    odom_alt_.erase(odom_alt_.begin(), keep_odom);
}

}  // namespace superloc::localization
