#include "plane_refine.h"

#include <superloc/core/se3.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace superloc::reloc {

namespace {

/// Point-to-plane residuals of every point at T in one level; fills H, g (perturbation
/// [dt; dw] about the sensor position: q' = exp(dw) (q - t) + t + dt) and the inlier statistics.
void linearize(const map::VoxelMap& vm, int level, const std::vector<Vec3f>& pts, const SE3d& T, double kernel,
               double inlier_dist, Mat6d& H, Vec6d& g, size_t& inliers, double& sq) {
    H.setZero();
    g.setZero();
    inliers = 0;
    sq = 0;
    const double max_r = vm.levelSize(level);
    const Vec3d t = T.translation();
    for (const auto& pf : pts) {
        const Vec3d q = T * pf.cast<double>();
        const map::VoxelStats* v = vm.find(level, q.cast<float>());
        if (!v) continue;
        // Plane quality as the localizer's voxel association weighs it (doc/map.md): a voxel
        // whose points are as thick as a tenth of its edge is not a plane.
        const double fit = 1.0 - v->thickness / std::max(0.05, 0.1 * max_r);
        if (fit <= 0) continue;
        const Vec3d n = v->normal.cast<double>();
        const double r = n.dot(q - v->mean.cast<double>());
        if (std::abs(r) > max_r) continue;
        if (std::abs(r) < inlier_dist) ++inliers, sq += r * r;
        const double w = fit / (1.0 + (r / kernel) * (r / kernel));
        Vec6d J;
        J.head<3>() = n;
        J.tail<3>() = (q - t).cross(n);
        H.noalias() += w * J * J.transpose();
        g.noalias() += w * J * r;
    }
}

}  // namespace

RefineResult refinePointToPlane(const map::VoxelMap& vm, const std::vector<Vec3f>& pts, const SE3d& T0,
                                int iterations, double inlier_dist) {
    RefineResult res;
    res.T_map_lidar = T0;
    if (vm.levels() == 0 || pts.empty()) return res;
    SE3d T = T0;
    Mat6d H;
    Vec6d g;
    size_t inl = 0;
    double sq = 0;
    linearize(vm, 0, pts, T, 0.25 * vm.levelSize(0), inlier_dist, H, g, inl, sq);
    res.inliers_start = static_cast<double>(inl) / static_cast<double>(pts.size());
    // The hypothesis is within about a search cell and a yaw step: the 2 m level's planes
    // (corners mixed into one voxel) would only bias it; start at the 1 m level at most.
    for (int level = std::min(1, vm.levels() - 1); level >= 0; --level) {
        const double kernel = 0.25 * vm.levelSize(level);
        bool settled = false;
        for (int it = 0; it < iterations; ++it) {
            linearize(vm, level, pts, T, kernel, inlier_dist, H, g, inl, sq);
            if (H.trace() <= 0) break;
            // Levenberg-style damping: a direction no plane constrains (a corridor's axis) stays put.
            const Mat6d A = H + (1e-3 * H.trace() / 6.0) * Mat6d::Identity();
            const Vec6d d = -A.ldlt().solve(g);
            if (!d.allFinite()) break;
            T.translation() += d.head<3>();
            T.linear() = expSO3(d.tail<3>()) * T.linear();
            T = orthonormalize(T);
            if (d.head<3>().norm() < 1e-3 && d.tail<3>().norm() < 1e-4) {
                settled = true;
                break;
            }
        }
        if (level == 0) res.converged = settled;
    }
    linearize(vm, 0, pts, T, 0.25 * vm.levelSize(0), inlier_dist, H, g, inl, sq);
    res.T_map_lidar = T;
    res.inliers = static_cast<double>(inl) / static_cast<double>(pts.size());
    res.rms = inl ? std::sqrt(sq / static_cast<double>(inl)) : 0.0;
    return res;
}

}  // namespace superloc::reloc
