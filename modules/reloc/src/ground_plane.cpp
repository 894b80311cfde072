// Ground plane of a scan by RANSAC (doc/relocalization.md §2).
#include <superloc/reloc/ground_plane.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>

namespace superloc::reloc {

double yawOf(const Mat3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

Mat3d removeYaw(const Mat3d& R) {
    return Eigen::AngleAxisd(-yawOf(R), Vec3d::UnitZ()).toRotationMatrix() * R;
}

namespace {

/// Least-squares plane through `pts`: unit normal (smallest covariance eigenvector) and centroid.
bool fitPlane(const std::vector<Vec3d>& pts, Vec3d& normal, Vec3d& centroid) {
    if (pts.size() < 3) return false;
    centroid.setZero();
    for (const auto& p : pts) centroid += p;
    centroid /= static_cast<double>(pts.size());
    Mat3d C = Mat3d::Zero();
    for (const auto& p : pts) C += (p - centroid) * (p - centroid).transpose();
    Eigen::SelfAdjointEigenSolver<Mat3d> es(C);
    normal = es.eigenvectors().col(0);
    return normal.allFinite();
}

}  // namespace

GroundPlane estimateGroundPlane(const std::vector<Vec3f>& points_lidar, const GroundPlaneParams& params,
                                const Mat3d* R_level_lidar) {
    GroundPlane g;
    const Mat3d R = R_level_lidar ? removeYaw(*R_level_lidar) : Mat3d::Identity();
    const double max_tilt = (R_level_lidar ? 5.0 : params.max_tilt_deg) * M_PI / 180.0;
    const double cos_tilt = std::cos(max_tilt);
    // Candidates, in the frame the plane is searched in (lidar, or levelled with an IMU).
    std::vector<Vec3d> cand;
    cand.reserve(points_lidar.size() / 4);
    for (const auto& pf : points_lidar) {
        if (!pf.allFinite()) continue;
        const Vec3d p = R * pf.cast<double>();
        const double rh = std::hypot(p.x(), p.y());
        if (p.z() < -0.5 * params.min_height && rh < params.max_range && p.norm() > 0.5) cand.push_back(p);
    }
    // At most ~4000 candidates, taken evenly (RANSAC cost and determinism).
    if (cand.size() > 4000) {
        std::vector<Vec3d> sub;
        const double step = static_cast<double>(cand.size()) / 4000.0;
        for (double i = 0; i < static_cast<double>(cand.size()); i += step) sub.push_back(cand[static_cast<size_t>(i)]);
        cand.swap(sub);
    }
    g.candidates = cand.size();
    if (cand.size() < std::max<size_t>(3, params.min_inliers)) return g;

    std::mt19937 rng(params.seed);
    std::uniform_int_distribution<size_t> pick(0, cand.size() - 1);
    size_t best_count = 0;
    Vec3d best_n = Vec3d::UnitZ();
    double best_d = 0;  // plane: n . p + d = 0, n up; sensor height = d
    for (int it = 0; it < params.iterations; ++it) {
        const Vec3d& a = cand[pick(rng)];
        const Vec3d& b = cand[pick(rng)];
        const Vec3d& c = cand[pick(rng)];
        Vec3d n = (b - a).cross(c - a);
        const double nn = n.norm();
        if (nn < 1e-6) continue;
        n /= nn;
        if (n.z() < 0) n = -n;
        if (n.z() < cos_tilt) continue;
        const double d = -n.dot(a);
        if (d < params.min_height || d > params.max_height) continue;
        size_t count = 0;
        for (const auto& p : cand)
            if (std::abs(n.dot(p) + d) < params.inlier_dist) ++count;
        if (count > best_count) best_count = count, best_n = n, best_d = d;
    }
    if (best_count < params.min_inliers) return g;
    // Least-squares refit on the inliers (twice: the inlier set moves with the plane).
    Vec3d n = best_n;
    double d = best_d;
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<Vec3d> in;
        for (const auto& p : cand)
            if (std::abs(n.dot(p) + d) < 1.5 * params.inlier_dist) in.push_back(p);
        Vec3d nn, c;
        if (!fitPlane(in, nn, c)) break;
        if (nn.z() < 0) nn = -nn;
        if (nn.z() < cos_tilt) break;
        n = nn;
        d = -n.dot(c);
    }
    g.inliers = 0;
    for (const auto& p : cand)
        if (std::abs(n.dot(p) + d) < params.inlier_dist) ++g.inliers;
    if (g.inliers < params.min_inliers || d < params.min_height || d > params.max_height) return g;
    g.found = true;
    g.height = d;
    if (R_level_lidar) {
        // Only the height is estimated; the tilt is the caller's.
        g.normal_lidar = R.transpose() * Vec3d::UnitZ();
        g.R_level_lidar = R;
    } else {
        g.normal_lidar = n;
        const Mat3d R_up = Eigen::Quaterniond::FromTwoVectors(n, Vec3d::UnitZ()).toRotationMatrix();
        g.R_level_lidar = removeYaw(R_up);
    }
    return g;
}

}  // namespace superloc::reloc
