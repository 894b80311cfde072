#include <superloc/core/se3.h>
#include <superloc/imu/preintegration.h>

#include <algorithm>

namespace superloc::imu {

SE3d NavState::pose() const {
    SE3d T = SE3d::Identity();
    T.linear() = R;
    T.translation() = p;
    return T;
}

NavState NavState::fromPose(const SE3d& T_map_imu, const Vec3d& v) {
    NavState s;
    s.R = T_map_imu.linear();
    s.p = T_map_imu.translation();
    s.v = v;
    return s;
}

Preintegration::Preintegration(const ImuBias& bias_lin, const ImuNoise& noise)
    : bias_lin_(bias_lin), noise_(noise) {}

void Preintegration::reset(const ImuBias& bias_lin) { *this = Preintegration(bias_lin, noise_); }

void Preintegration::integrate(const Vec3d& acc, const Vec3d& gyro, double dt) {
    if (dt <= 0) return;
    const Vec3d a = acc - bias_lin_.acc;
    const Vec3d w = gyro - bias_lin_.gyro;
    const Vec3d phi = w * dt;
    const Mat3d dRk = expSO3(phi);
    const Mat3d Jr = rightJacobianSO3(phi);
    const Mat3d a_x = skew(a);
    const double dt2 = dt * dt;
    // The acceleration is rotated with the attitude at mid-interval (second-order accurate for
    // rotating sensors; Forster's zero-order hold uses the start attitude).
    const Mat3d Rm = dR_ * expSO3(0.5 * phi);

    // Covariance propagation (Forster eq. 63), error order (rotation, velocity, position).
    Mat9d A = Mat9d::Identity();
    A.block<3, 3>(0, 0) = dRk.transpose();
    A.block<3, 3>(3, 0) = -Rm * a_x * dt;
    A.block<3, 3>(6, 0) = -0.5 * Rm * a_x * dt2;
    A.block<3, 3>(6, 3) = Mat3d::Identity() * dt;
    Eigen::Matrix<double, 9, 3> Bg = Eigen::Matrix<double, 9, 3>::Zero();
    Eigen::Matrix<double, 9, 3> Ba = Eigen::Matrix<double, 9, 3>::Zero();
    Bg.block<3, 3>(0, 0) = Jr * dt;
    Ba.block<3, 3>(3, 0) = Rm * dt;
    Ba.block<3, 3>(6, 0) = 0.5 * Rm * dt2;
    // Discrete noise covariance from continuous densities: sigma_d^2 = sigma_c^2 / dt.
    const double qg = noise_.gyro * noise_.gyro / dt;
    const double qa = noise_.acc * noise_.acc / dt;
    cov_ = A * cov_ * A.transpose() + qg * Bg * Bg.transpose() + qa * Ba * Ba.transpose();

    // Bias Jacobians (Forster appendix, eq. 69), before dR_ is updated.
    dp_dba_ += dv_dba_ * dt - 0.5 * Rm * dt2;
    dp_dbg_ += dv_dbg_ * dt - 0.5 * Rm * a_x * dR_dbg_ * dt2;
    dv_dba_ += -Rm * dt;
    dv_dbg_ += -Rm * a_x * dR_dbg_ * dt;
    dR_dbg_ = dRk.transpose() * dR_dbg_ - Jr * dt;

    // Increments (Forster eq. 35).
    dp_ += dv_ * dt + 0.5 * Rm * a * dt2;
    dv_ += Rm * a * dt;
    dR_ = dR_ * dRk;
    dt_ += dt;
}

Mat3d Preintegration::correctedDeltaR(const ImuBias& b) const {
    return dR_ * expSO3(dR_dbg_ * (b.gyro - bias_lin_.gyro));
}

Vec3d Preintegration::correctedDeltaV(const ImuBias& b) const {
    return dv_ + dv_dba_ * (b.acc - bias_lin_.acc) + dv_dbg_ * (b.gyro - bias_lin_.gyro);
}

Vec3d Preintegration::correctedDeltaP(const ImuBias& b) const {
    return dp_ + dp_dba_ * (b.acc - bias_lin_.acc) + dp_dbg_ * (b.gyro - bias_lin_.gyro);
}

NavState Preintegration::predict(const NavState& i, const ImuBias& b, const Vec3d& g_map) const {
    NavState j;
    j.R = i.R * correctedDeltaR(b);
    j.v = i.v + g_map * dt_ + i.R * correctedDeltaV(b);
    j.p = i.p + i.v * dt_ + 0.5 * g_map * dt_ * dt_ + i.R * correctedDeltaP(b);
    // Keep R orthonormal after many products.
    j.R = Eigen::Quaterniond(j.R).normalized().toRotationMatrix();
    return j;
}

bool coversInterval(const std::vector<ImuSample>& samples, double t0, double t1, double max_gap) {
    if (samples.empty() || samples.front().t > t0 + max_gap || samples.back().t < t1 - max_gap) return false;
    // From the last sample at or before t0 (or the first one) to the first at or after t1.
    auto it = std::upper_bound(samples.begin(), samples.end(), t0,
                               [](double t, const ImuSample& s) { return t < s.t; });
    if (it != samples.begin()) --it;
    for (; it + 1 != samples.end() && it->t < t1; ++it)
        if ((it + 1)->t - it->t > max_gap) return false;
    return true;
}

size_t integrateInterval(
    const std::vector<ImuSample>& samples, double t0, double t1, Preintegration& pre) {
    if (samples.empty() || t1 <= t0) return 0;
    // First sample whose hold interval [t_k, t_{k+1}) reaches past t0.
    auto it = std::upper_bound(
        samples.begin(), samples.end(), t0, [](double t, const ImuSample& s) { return t < s.t; });
    if (it != samples.begin()) --it;
    size_t used = 0;
    for (; it != samples.end(); ++it) {
        const double start = (it == samples.begin() && it->t > t0) ? t0 : std::max(it->t, t0);
        if (start >= t1) break;
        const auto nxt = it + 1;
        const double end = (nxt == samples.end()) ? t1 : std::min(nxt->t, t1);
        if (end > start) {
            pre.integrate(it->acc, it->gyro, end - start);
            ++used;
        }
    }
    return used;
}

std::vector<SE3d> predictPoses(const std::vector<ImuSample>& samples, double t0, const NavState& start,
                               const ImuBias& b, const Vec3d& g_map, const std::vector<double>& times) {
    std::vector<SE3d> out;
    out.reserve(times.size());
    Preintegration pre(b);
    double reached = t0;
    for (const double tau : times) {
        if (tau <= t0) {
            NavState back = start;
            back.p += start.v * (tau - t0);
            out.push_back(back.pose());
            continue;
        }
        if (tau > reached) integrateInterval(samples, reached, tau, pre), reached = tau;
        out.push_back(pre.predict(start, b, g_map).pose());
    }
    return out;
}

SweepPoses sweepPoses(const std::vector<ImuSample>& samples, double t0, const NavState& start, const ImuBias& b,
                      const Vec3d& g_map, double t_scan, double s_min, const SE3d& T_imu_sensor, int n) {
    SweepPoses out;
    std::vector<double> times(static_cast<size_t>(n) + 1);
    out.s.resize(times.size());
    for (int j = 0; j <= n; ++j) {
        out.s[static_cast<size_t>(j)] = s_min * (n - j) / n;
        times[static_cast<size_t>(j)] = t_scan + out.s[static_cast<size_t>(j)];
    }
    const std::vector<SE3d> T_map_imu = predictPoses(samples, t0, start, b, g_map, times);
    const SE3d T_sensor_end_map = (T_map_imu.back() * T_imu_sensor).inverse();
    out.T_end_s.resize(T_map_imu.size());
    for (size_t j = 0; j < T_map_imu.size(); ++j) out.T_end_s[j] = T_sensor_end_map * T_map_imu[j] * T_imu_sensor;
    return out;
}

}  // namespace superloc::imu
