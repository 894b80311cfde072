// A synthetic box room for the Localizer's tests: scans ray-cast per point along a rotating,
// accelerating trajectory (per-point time, 0.5 rad/s yaw), and the analytic motion the IMU
// samples are taken from.
#pragma once

#include <superloc/core/se3.h>
#include <superloc/core/types.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace superloc::testing {

inline const Vec3d kG(0, 0, -9.81);
inline const Vec3d kRoomMin(-6, -4, 0), kRoomMax(6, 4, 3);

struct Motion {  // starts at rest in position (or at v0), turning at a constant body rate
    Mat3d R0 = makePoseRPY(0, 0, 0, 0.02, -0.01, 0.3).linear();
    Vec3d w_b = Vec3d(0.05, -0.03, 0.5);
    Vec3d v0 = Vec3d::Zero();  ///< [m/s] constant velocity added to the motion (a start in motion)
    double bob = 0;            ///< [m] amplitude of a vertical 7 Hz bobbing (a car's or a walker's gait)
    static constexpr double kBobOmega = 2 * M_PI * 7.0;
    Mat3d R(double t) const { return R0 * expSO3(w_b * t); }
    Vec3d p(double t) const {
        return Vec3d(0.4 * (t - std::sin(t)) - 2.0, 0.3 * (1 - std::cos(0.8 * t)), 1.2 + bob * std::sin(kBobOmega * t)) +
               v0 * t;
    }
    Vec3d a(double t) const {
        return {0.4 * std::sin(t), 0.192 * std::cos(0.8 * t), -bob * kBobOmega * kBobOmega * std::sin(kBobOmega * t)};
    }
    SE3d T(double t) const {
        SE3d T = SE3d::Identity();
        T.linear() = R(t);
        T.translation() = p(t);
        return T;
    }
};

// Distance along unit ray (o, d) to the inside of the box room.
inline double castBox(const Vec3d& o, const Vec3d& d) {
    double best = 1e9;
    for (int k = 0; k < 3; ++k) {
        if (std::abs(d[k]) < 1e-9) continue;
        for (double wall : {kRoomMin[k], kRoomMax[k]}) {
            const double t = (wall - o[k]) / d[k];
            if (t > 1e-6) best = std::min(best, t);
        }
    }
    return best;
}

inline PointCloud boxSurface(double step) {
    PointCloud c;
    for (double x = kRoomMin.x(); x <= kRoomMax.x(); x += step)
        for (double y = kRoomMin.y(); y <= kRoomMax.y(); y += step)
            for (double z : {kRoomMin.z(), kRoomMax.z()}) c.points.emplace_back(x, y, z);
    for (double z = kRoomMin.z(); z <= kRoomMax.z(); z += step) {
        for (double x = kRoomMin.x(); x <= kRoomMax.x(); x += step)
            for (double y : {kRoomMin.y(), kRoomMax.y()}) c.points.emplace_back(x, y, z);
        for (double y = kRoomMin.y(); y <= kRoomMax.y(); y += step)
            for (double x : {kRoomMin.x(), kRoomMax.x()}) c.points.emplace_back(x, y, z);
    }
    return c;
}

// One 0.1 s sweep ending at t_end: 16 rings x 360 columns, column j fired at its own time.
inline Scan sweep(const Motion& m, const SE3d& T_imu_lidar, double t_end) {
    Scan s;
    s.t = t_end;
    s.T_imu_lidar = T_imu_lidar;
    const int cols = 360, rings = 16;
    for (int j = 0; j < cols; ++j) {
        const double rel = -0.1 + 0.1 * (j + 1) / cols;
        const SE3d T_map_lidar = m.T(t_end + rel) * T_imu_lidar;
        const double az = 2 * M_PI * j / cols;
        for (int r = 0; r < rings; ++r) {
            const double el = (-15.0 + 2.0 * r) * M_PI / 180;
            const Vec3d d_l(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
            const double range = castBox(T_map_lidar.translation(), T_map_lidar.linear() * d_l);
            s.points.push_back((d_l * range).cast<float>());
            s.rel_time.push_back(static_cast<float>(rel));
        }
    }
    return s;
}

/// The IMU samples (200 Hz, each value held over its interval) of the motion from t_imu up to
/// t; t_imu moves on past them.
inline std::vector<ImuSample> imuUpTo(const Motion& m, double t, double& t_imu) {
    const double dt = 0.005;
    std::vector<ImuSample> out;
    for (; t_imu <= t + 1e-9; t_imu += dt) {
        ImuSample s;
        s.t = t_imu;
        const double tm = t_imu + 0.5 * dt;  // value held over [t, t + dt)
        s.acc = m.R(tm).transpose() * (m.a(tm) - kG);
        s.gyro = m.w_b;
        out.push_back(s);
    }
    return out;
}

}  // namespace superloc::testing
