// Small synthetic maps and scans for the global-search tests: an L-shaped hall with pillars,
// two copies of it side by side, a long featureless corridor; scans by a spherical z-buffer
// (the nearest map point per beam), with noise.
#pragma once

#include <superloc/core/se3.h>
#include <superloc/core/types.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <unordered_map>
#include <vector>

namespace superloc::testing {

inline void addPlaneRect(std::vector<Vec3f>& pts, const Vec3d& o, const Vec3d& u, const Vec3d& v, double step) {
    const double lu = u.norm(), lv = v.norm();
    for (double a = 0; a <= lu; a += step)
        for (double b = 0; b <= lv; b += step) pts.push_back((o + u * (a / lu) + v * (b / lv)).cast<float>());
}

/// Vertical wall from (x0,y0) to (x1,y1), height h, standing on z0.
inline void addWall(std::vector<Vec3f>& pts, double x0, double y0, double x1, double y1, double h, double step,
                    double z0 = 0) {
    addPlaneRect(pts, {x0, y0, z0}, {x1 - x0, y1 - y0, 0}, {0, 0, h}, step);
}

/// Axis-aligned box's four sides and top.
inline void addBox(std::vector<Vec3f>& pts, double cx, double cy, double sx, double sy, double h, double step) {
    const double x0 = cx - sx / 2, x1 = cx + sx / 2, y0 = cy - sy / 2, y1 = cy + sy / 2;
    addWall(pts, x0, y0, x1, y0, h, step);
    addWall(pts, x1, y0, x1, y1, h, step);
    addWall(pts, x1, y1, x0, y1, h, step);
    addWall(pts, x0, y1, x0, y0, h, step);
    addPlaneRect(pts, {x0, y0, h}, {sx, 0, 0}, {0, sy, 0}, step);
}

/// L-shaped hall [0,20]x[0,8] u [0,8]x[0,20], walls 3 m, pillars and a table; shifted by `off`.
inline std::vector<Vec3f> lHall(const Vec3d& off = Vec3d::Zero(), double step = 0.1) {
    std::vector<Vec3f> p;
    addPlaneRect(p, {0, 0, 0}, {20, 0, 0}, {0, 8, 0}, step);
    addPlaneRect(p, {0, 8, 0}, {8, 0, 0}, {0, 12, 0}, step);
    const double h = 3;
    addWall(p, 0, 0, 20, 0, h, step);
    addWall(p, 20, 0, 20, 8, h, step);
    addWall(p, 20, 8, 8, 8, h, step);
    addWall(p, 8, 8, 8, 20, h, step);
    addWall(p, 8, 20, 0, 20, h, step);
    addWall(p, 0, 20, 0, 0, h, step);
    addBox(p, 4, 4, 0.6, 0.6, h, step);
    addBox(p, 14, 3, 0.6, 0.6, h, step);
    addBox(p, 3, 15, 0.6, 0.6, h, step);
    addBox(p, 16, 6, 1.5, 0.8, 0.8, step);
    for (auto& q : p) q += off.cast<float>();
    return p;
}

/// Corridor along x, [0, length] x [0, 3], walls 3 m high, open ends, floor.
inline std::vector<Vec3f> corridor(double length, double step = 0.1) {
    std::vector<Vec3f> p;
    addPlaneRect(p, {0, 0, 0}, {length, 0, 0}, {0, 3, 0}, step);
    addWall(p, 0, 0, length, 0, 3, step);
    addWall(p, 0, 3, length, 3, 3, step);
    return p;
}

/// A scan of `map` from T_map_lidar: per beam (az x el cell of `az_deg` x `el_deg` within
/// +-fov/2 of the lidar's xy plane) the nearest map point in range, with Gaussian range noise.
inline std::vector<Vec3f> scanFrom(const std::vector<Vec3f>& map, const SE3d& T_map_lidar, double max_range = 40,
                                   double noise = 0.02, double az_deg = 0.5, double el_deg = 1.0,
                                   double fov_deg = 90, unsigned seed = 7) {
    const SE3d T_lidar_map = T_map_lidar.inverse();
    std::unordered_map<long, Vec3d> beams;
    for (const auto& m : map) {
        const Vec3d q = T_lidar_map * m.cast<double>();
        const double r = q.norm();
        if (r < 0.5 || r > max_range) continue;
        const double el = std::asin(q.z() / r) * 180 / M_PI;
        if (std::abs(el) > fov_deg / 2) continue;
        const double az = std::atan2(q.y(), q.x()) * 180 / M_PI + 180;
        const long key = static_cast<long>(az / az_deg) * 100000 + static_cast<long>((el + 90) / el_deg);
        auto it = beams.find(key);
        if (it == beams.end() || it->second.norm() > r) beams[key] = q;
    }
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0, noise);
    std::vector<Vec3f> out;
    out.reserve(beams.size());
    for (const auto& [k, q] : beams) {
        (void)k;
        out.push_back((q * (1 + n(rng) / q.norm())).cast<float>());
    }
    // Deterministic order (unordered_map iteration is not).
    std::sort(out.begin(), out.end(), [](const Vec3f& a, const Vec3f& b) {
        return a.x() != b.x() ? a.x() < b.x() : a.y() != b.y() ? a.y() < b.y() : a.z() < b.z();
    });
    return out;
}

}  // namespace superloc::testing
