#include <superloc/core/se3.h>

#include <algorithm>
#include <cmath>

namespace superloc {

Mat3d skew(const Vec3d& v) {
    Mat3d S;
    S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    return S;
}

Mat3d expSO3(const Vec3d& phi) {
    const double theta2 = phi.squaredNorm();
    const Mat3d K = skew(phi);
    if (theta2 < 1e-12) {
        return Mat3d::Identity() + K + 0.5 * K * K;
    }
    const double theta = std::sqrt(theta2);
    return Mat3d::Identity() + (std::sin(theta) / theta) * K +
           ((1.0 - std::cos(theta)) / theta2) * K * K;
}

Vec3d logSO3(const Mat3d& R) {
    // Quaternion route: numerically stable for every angle, including near pi.
    Eigen::Quaterniond q(R);
    q.normalize();
    if (q.w() < 0) q.coeffs() *= -1.0;
    const double sin_half = q.vec().norm();
    if (sin_half < 1e-12) return 2.0 * q.vec();
    const double theta = 2.0 * std::atan2(sin_half, q.w());
    return (theta / sin_half) * q.vec();
}

Mat3d rightJacobianSO3(const Vec3d& phi) {
    const double theta2 = phi.squaredNorm();
    const Mat3d K = skew(phi);
    if (theta2 < 1e-10) return Mat3d::Identity() - 0.5 * K + K * K / 6.0;
    const double theta = std::sqrt(theta2);
    return Mat3d::Identity() - ((1.0 - std::cos(theta)) / theta2) * K +
           ((theta - std::sin(theta)) / (theta2 * theta)) * K * K;
}

Mat3d rightJacobianInvSO3(const Vec3d& phi) {
    const double theta2 = phi.squaredNorm();
    const Mat3d K = skew(phi);
    if (theta2 < 1e-10) return Mat3d::Identity() + 0.5 * K + K * K / 12.0;
    const double theta = std::sqrt(theta2);
    return Mat3d::Identity() + 0.5 * K +
           (1.0 / theta2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta))) * K * K;
}

Vec6d toVec6(const SE3d& T) {
    Vec6d v;
    v.head<3>() = T.translation();
    v.tail<3>() = logSO3(T.linear());
    return v;
}

SE3d fromVec6(const Vec6d& v) {
    SE3d T = SE3d::Identity();
    T.linear() = expSO3(v.tail<3>());
    T.translation() = v.head<3>();
    return T;
}

SE3d makePose(double x, double y, double z, double qx, double qy, double qz, double qw) {
    Eigen::Quaterniond q(qw, qx, qy, qz);
    q.normalize();
    SE3d T = SE3d::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() = Vec3d(x, y, z);
    return T;
}

SE3d turnedAboutVertical(const SE3d& T, double yaw) {
    SE3d out = T;
    out.linear() = Eigen::AngleAxisd(yaw, Vec3d::UnitZ()).toRotationMatrix() * T.linear();
    return out;
}

SE3d makePoseRPY(double x, double y, double z, double roll, double pitch, double yaw) {
    SE3d T = SE3d::Identity();
    T.linear() = (Eigen::AngleAxisd(yaw, Vec3d::UnitZ()) *
                  Eigen::AngleAxisd(pitch, Vec3d::UnitY()) *
                  Eigen::AngleAxisd(roll, Vec3d::UnitX()))
                     .toRotationMatrix();
    T.translation() = Vec3d(x, y, z);
    return T;
}

SE3d interpolate(const SE3d& a, const SE3d& b, double s) {
    const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
    SE3d T = SE3d::Identity();
    T.linear() = qa.slerp(s, qb).normalized().toRotationMatrix();
    T.translation() = (1.0 - s) * a.translation() + s * b.translation();
    return T;
}

std::optional<SE3d> interpolateAt(const Trajectory& traj, double t, double max_gap, double tol) {
    if (traj.empty()) return std::nullopt;
    if (t < traj.front().t - tol || t > traj.back().t + tol) return std::nullopt;
    if (traj.size() == 1) return traj.front().pose;
    auto it = std::lower_bound(traj.begin(), traj.end(), t,
                               [](const PoseStamped& p, double v) { return p.t < v; });
    if (it == traj.begin()) return it->pose;
    if (it == traj.end()) return traj.back().pose;
    const PoseStamped& b = *it;
    const PoseStamped& a = *(it - 1);
    const double dt = b.t - a.t;
    if (dt > max_gap) return std::nullopt;
    if (dt <= 0) return b.pose;
    return interpolate(a.pose, b.pose, std::clamp((t - a.t) / dt, 0.0, 1.0));
}

double translationDistance(const SE3d& a, const SE3d& b) {
    return (a.translation() - b.translation()).norm();
}

double rotationAngle(const SE3d& a, const SE3d& b) {
    return logSO3(a.linear().transpose() * b.linear()).norm();
}

SE3d orthonormalize(const SE3d& T) {
    SE3d out = T;
    out.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
    return out;
}

}  // namespace superloc
