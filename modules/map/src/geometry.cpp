// Local PCA of a point neighbourhood: normal, planarity, linearity and plane-fit residual.
#include <superloc/map/prior_map.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace superloc::map {

PointGeometry fitNeighborhood(const std::vector<Vec3f>& pts) {
    PointGeometry g;
    g.fit_residual = std::numeric_limits<float>::infinity();
    const size_t n = pts.size();
    if (n < 3) return g;
    Vec3d mean = Vec3d::Zero();
    for (const auto& p : pts) mean += p.cast<double>();
    mean /= static_cast<double>(n);
    Mat3d cov = Mat3d::Zero();
    for (const auto& p : pts) {
        const Vec3d d = p.cast<double>() - mean;
        cov += d * d.transpose();
    }
    cov /= static_cast<double>(n);
    // Eigenvalues in increasing order: l3 <= l2 <= l1.
    const Eigen::SelfAdjointEigenSolver<Mat3d> es(cov);
    const Vec3d ev = es.eigenvalues().cwiseMax(0.0);
    const double l3 = ev(0), l2 = ev(1), l1 = ev(2);
    if (!(l1 > 1e-12)) return g;
    g.normal = es.eigenvectors().col(0).normalized().cast<float>();
    g.planarity = static_cast<float>((l2 - l3) / l1);
    g.linearity = static_cast<float>((l1 - l2) / l1);
    g.fit_residual = static_cast<float>(std::sqrt(l3));
    return g;
}

}  // namespace superloc::map
