// Shared by the OdomCalibration tests (test_odom_calibration.cpp: the fit; test_odom_worth.cpp:
// what the corrected odometry is worth out of sample): a true body motion and an odometer that
// errs systematically on it.
#pragma once

#include <superloc/core/se3.h>

#include <array>
#include <cmath>
#include <random>

namespace superloc::testing {

/// A frame of true body motion: 0.5 m forward with a little sideways weave and turning.
inline SE3d trueMotion(int k) {
    return makePoseRPY(0.5, 0.02 * std::sin(0.3 * k), 0.003 * std::cos(0.5 * k), 0.002 * std::sin(0.7 * k),
                       0.001 * std::cos(0.4 * k), 0.05 * std::sin(0.2 * k));
}

/// What an odometer with drift b per metre (body), rotation scale s (all axes), heading slip c
/// [rad/m] and white noise reports for the true motion `m`.
inline SE3d odometer(const SE3d& m, const Vec3d& b, double s, double c, double noise_m, double noise_rad,
                   std::mt19937& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    const double d = m.translation().norm();
    Vec3d phi = (1 + s) * logSO3(m.linear());
    phi.z() += c * d;
    phi += noise_rad * Vec3d(n(rng), n(rng), n(rng));
    SE3d out = SE3d::Identity();
    out.linear() = expSO3(phi);
    out.translation() = m.translation() + b * d + noise_m * Vec3d(n(rng), n(rng), n(rng));
    return out;
}

inline std::array<bool, 6> all() {
    std::array<bool, 6> h{};
    h.fill(true);
    return h;
}

}  // namespace superloc::testing
