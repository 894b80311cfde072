#include <superloc/core/mrpt_conversions.h>

namespace superloc {

SE3d toEigen(const mrpt::poses::CPose3D& p) {
    SE3d T = SE3d::Identity();
    T.matrix() = p.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
    return T;
}

mrpt::poses::CPose3D toMrpt(const SE3d& T) {
    return mrpt::poses::CPose3D(mrpt::math::CMatrixDouble44(T.matrix()));
}

// Permutation between (x y z yaw pitch roll) and (x y z roll pitch yaw): swap indices 3 and 5.
static Mat6d swapYawRoll(const Mat6d& in) {
    Eigen::Matrix<double, 6, 6> P = Eigen::Matrix<double, 6, 6>::Zero();
    const int perm[6] = {0, 1, 2, 5, 4, 3};
    for (int i = 0; i < 6; ++i) P(i, perm[i]) = 1.0;
    return P * in * P.transpose();
}

Mat6d covFromMrpt(const mrpt::math::CMatrixDouble66& cov) { return swapYawRoll(cov.asEigen()); }

mrpt::math::CMatrixDouble66 covToMrpt(const Mat6d& cov) {
    return mrpt::math::CMatrixDouble66(swapYawRoll(cov));
}

}  // namespace superloc
