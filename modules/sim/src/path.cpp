#include <superloc/sim/path.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace superloc::sim {
namespace {

struct RawPoint {
    Vec3d p;
    double speed;  // fraction of max_speed
};

// Corner fillets: each inner waypoint B is replaced by a quadratic Bezier from B - u1 d to
// B + u2 d with control point B (tangent-continuous, close to a circular arc of radius r).
std::vector<RawPoint> filletPolyline(const std::vector<Waypoint>& w, double radius, double step) {
    std::vector<RawPoint> out;
    const auto addSegment = [&](const Vec3d& a, const Vec3d& b, double sp) {
        const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
        for (int k = (out.empty() ? 0 : 1); k <= n; ++k)
            out.push_back({a + (b - a) * (double(k) / n), sp});
    };
    Vec3d cur = w.front().p;
    for (size_t i = 1; i < w.size(); ++i) {
        const Vec3d& B = w[i].p;
        if (i + 1 == w.size()) {
            addSegment(cur, B, w[i - 1].speed);
            break;
        }
        const Vec3d& A = w[i - 1].p;
        const Vec3d& C = w[i + 1].p;
        const Vec3d u1 = (B - A).normalized(), u2 = (C - B).normalized();
        const double theta = std::acos(std::clamp(u1.dot(u2), -1.0, 1.0));
        if (theta < 1e-3) {
            addSegment(cur, B, w[i - 1].speed);
            cur = B;
            continue;
        }
        const double d = std::min({radius * std::tan(std::min(theta, 3.0) / 2),
                                   0.45 * (B - A).norm(), 0.45 * (C - B).norm()});
        const Vec3d P1 = B - u1 * d, P2 = B + u2 * d;
        addSegment(cur, P1, w[i - 1].speed);
        const double sp = std::min(w[i - 1].speed, w[i].speed);
        const int n = std::max(2, static_cast<int>(std::ceil(2 * d / step)));
        for (int k = 1; k <= n; ++k) {
            const double s = double(k) / n;
            out.push_back({(1 - s) * (1 - s) * P1 + 2 * s * (1 - s) * B + s * s * P2, sp});
        }
        cur = P2;
    }
    return out;
}

}  // namespace

DensePath makeDensePath(const std::vector<Waypoint>& waypoints, const MotionLimits& lim,
                        double step) {
    if (waypoints.size() < 2) throw std::runtime_error("path needs at least two waypoints");
    const auto raw = filletPolyline(waypoints, lim.corner_radius, step);
    DensePath path;
    for (const auto& r : raw)
        if (path.p.empty() || (r.p - path.p.back()).norm() > 1e-6) {
            path.p.push_back(r.p);
            path.v.push_back(std::clamp(r.speed, 0.01, 1.0) * lim.max_speed);
        }
    const size_t n = path.p.size();
    if (n < 2) throw std::runtime_error("path has zero length");
    path.s.assign(n, 0);
    for (size_t i = 1; i < n; ++i) path.s[i] = path.s[i - 1] + (path.p[i] - path.p[i - 1]).norm();

    // Speed caps from curvature (turning angle over +-0.2 m), then acceleration limits.
    const auto indexAt = [&](double s) {
        return static_cast<size_t>(
            std::lower_bound(path.s.begin(), path.s.end(), std::clamp(s, 0.0, path.s.back())) -
            path.s.begin());
    };
    for (size_t i = 0; i < n; ++i) {
        const size_t a = indexAt(path.s[i] - 0.2), b = indexAt(path.s[i] + 0.2);
        if (a == i || b == i || b >= n) continue;
        const Vec3d t1 = (path.p[i] - path.p[a]).normalized(),
                    t2 = (path.p[b] - path.p[i]).normalized();
        const double ang = std::acos(std::clamp(t1.dot(t2), -1.0, 1.0));
        // The two chords turn by the arc between their midpoints, (s[b] - s[a]) / 2.
        const double kappa = ang / std::max(1e-6, 0.5 * (path.s[b] - path.s[a]));
        if (kappa > 1e-6)
            path.v[i] = std::min(
                {path.v[i], lim.max_yaw_rate / kappa, std::sqrt(lim.max_lat_accel / kappa)});
    }
    path.v.front() = 0;
    path.v.back() = 0;
    for (size_t i = 1; i < n; ++i)
        path.v[i] = std::min(path.v[i], std::sqrt(path.v[i - 1] * path.v[i - 1] +
                                                  2 * lim.max_accel * (path.s[i] - path.s[i - 1])));
    for (size_t i = n - 1; i-- > 0;)
        path.v[i] = std::min(path.v[i], std::sqrt(path.v[i + 1] * path.v[i + 1] +
                                                  2 * lim.max_accel * (path.s[i + 1] - path.s[i])));
    path.t.assign(n, 0);
    for (size_t i = 1; i < n; ++i)
        path.t[i] = path.t[i - 1] +
                    2 * (path.s[i] - path.s[i - 1]) / std::max(1e-3, path.v[i - 1] + path.v[i]);
    return path;
}

Vec3d DensePath::positionAt(double time, Vec3d* tangent) const {
    const double tc = std::clamp(time, 0.0, duration());
    size_t i = static_cast<size_t>(std::upper_bound(t.begin(), t.end(), tc) - t.begin());
    i = std::clamp<size_t>(i, 1, p.size() - 1);
    const double dt = t[i] - t[i - 1];
    const double f = dt > 0 ? (tc - t[i - 1]) / dt : 0;
    if (tangent) {
        // Tangent over a short window, so it turns smoothly along the dense polyline.
        const size_t a = i >= 6 ? i - 6 : 0, b = std::min(p.size() - 1, i + 5);
        *tangent = (p[b] - p[a]).normalized();
    }
    return p[i - 1] + (p[i] - p[i - 1]) * f;
}

}  // namespace superloc::sim
