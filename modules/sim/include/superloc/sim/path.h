// Platform paths: waypoints -> rounded dense polyline -> speed profile -> knots in time.
#pragma once

#include <superloc/core/types.h>

#include <vector>

namespace superloc::sim {

/// A waypoint of a world's route: position of the body (IMU) frame and the speed wanted on the
/// way to the next waypoint, as a fraction of the platform's max_speed.
struct Waypoint {
    Vec3d p = Vec3d::Zero();
    double speed = 1.0;  ///< (0, 1] x max_speed
};

/// Limits of the platform moving along the path.
struct MotionLimits {
    double max_speed = 1.0;      ///< [m/s]
    double max_yaw_rate = 1.0;   ///< [rad/s] caps speed in turns (v <= max_yaw_rate / curvature)
    double max_accel = 1.0;      ///< [m/s^2] along the path
    double max_lat_accel = 2.0;  ///< [m/s^2] caps speed in turns (v^2 <= a_lat / curvature)
    double corner_radius = 1.0;  ///< [m] fillet radius of waypoint corners
};

/// Dense polyline with arc length and speed profile (starts and ends at rest).
struct DensePath {
    std::vector<Vec3d> p;   ///< [m]
    std::vector<double> s;  ///< [m] arc length at each point
    std::vector<double> v;  ///< [m/s] speed at each point
    std::vector<double> t;  ///< [s] time at each point from the start (t[0] = 0)

    double length() const { return s.empty() ? 0 : s.back(); }
    double duration() const { return t.empty() ? 0 : t.back(); }
    /// Position, unit tangent and arc length at time `time` (clamped to [0, duration]).
    Vec3d positionAt(double time, Vec3d* tangent = nullptr) const;
};

/// Rounds the corners of the waypoint polyline (quadratic Bezier fillets of `corner_radius`),
/// samples it every `step` metres and computes a speed profile honouring the limits.
DensePath makeDensePath(const std::vector<Waypoint>& waypoints, const MotionLimits& limits,
                        double step = 0.05);

}  // namespace superloc::sim
