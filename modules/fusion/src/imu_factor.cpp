#include <superloc/fusion/imu_factor.h>

#include <Eigen/Cholesky>
#include <algorithm>

namespace superloc::fusion {

ImuFactor::ImuFactor(const imu::Preintegration& pre, const Vec3d& g_map, double acc_bias_rw,
                     double gyro_bias_rw)
    : pre_(pre), g_(g_map), dR_q_(pre.deltaR()) {
    dR_q_.normalize();
    Mat15d cov = Mat15d::Zero();
    cov.block<9, 9>(0, 0) = pre.covariance();
    const double dt = std::max(pre.dt(), 1e-3);
    cov.block<3, 3>(9, 9) = Mat3d::Identity() * acc_bias_rw * acc_bias_rw * dt;
    cov.block<3, 3>(12, 12) = Mat3d::Identity() * gyro_bias_rw * gyro_bias_rw * dt;
    // Floor: a very short interval must not give an unbounded information.
    cov += Mat15d::Identity() * 1e-10;
    const Mat15d info = cov.inverse();
    // sqrt_info^T sqrt_info = info.
    sqrt_info_ = Eigen::LLT<Mat15d>(info).matrixL().transpose();
}

ceres::CostFunction* ImuFactor::Create(const imu::Preintegration& pre, const Vec3d& g_map,
                                       double acc_bias_rw, double gyro_bias_rw) {
    return new ceres::AutoDiffCostFunction<ImuFactor, 15, 7, 9, 7, 9>(
        new ImuFactor(pre, g_map, acc_bias_rw, gyro_bias_rw));
}

}  // namespace superloc::fusion
