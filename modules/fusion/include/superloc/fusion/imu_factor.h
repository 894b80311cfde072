// IMU preintegration factor between the states i and j (Forster et al. 2015, eq. 45):
//   r_R = Log( (ΔR_ij Exp(dR/dbg δbg))^T R_i^T R_j )
//   r_v = R_i^T (v_j - v_i - g Δt) - (Δv_ij + dv/dba δba + dv/dbg δbg)
//   r_p = R_i^T (p_j - p_i - v_i Δt - g Δt^2 / 2) - (Δp_ij + dp/dba δba + dp/dbg δbg)
//   r_b = b_j - b_i                                   (bias random walk)
// with δb = b_i - b_lin, weighted by the square-root information of the preintegration
// covariance and of the random walk over Δt. Parameter blocks: pose_i (7), speed_bias_i (9),
// pose_j (7), speed_bias_j (9); poses T_map_imu on PoseManifold.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>
#include <superloc/imu/preintegration.h>

namespace superloc::fusion {

using Mat15d = Eigen::Matrix<double, 15, 15>;

struct ImuFactor {
    ImuFactor(const imu::Preintegration& pre, const Vec3d& g_map, double acc_bias_rw,
              double gyro_bias_rw);

    /// The 15 residuals (order: rotation, velocity, position, acc bias, gyro bias).
    template <typename T>
    bool operator()(const T* pose_i, const T* sb_i, const T* pose_j, const T* sb_j, T* res) const;

    /// The factor with analytic Jacobians (imu_factor.cpp), what the solves use.
    static ceres::CostFunction* Create(const imu::Preintegration& pre, const Vec3d& g_map,
                                       double acc_bias_rw, double gyro_bias_rw);
    /// The same factor differentiated automatically (tests: the analytic Jacobians against it).
    static ceres::CostFunction* CreateAutoDiff(const imu::Preintegration& pre, const Vec3d& g_map,
                                               double acc_bias_rw, double gyro_bias_rw);

    imu::Preintegration pre_;
    Vec3d g_;
    Mat15d sqrt_info_;
    Eigen::Quaterniond dR_q_;  ///< ΔR_ij as a quaternion (precomputed)
};

template <typename T>
bool ImuFactor::operator()(const T* pose_i, const T* sb_i, const T* pose_j, const T* sb_j,
                           T* res) const {
    using V3 = Eigen::Matrix<T, 3, 1>;
    using Q = Eigen::Quaternion<T>;
    const V3 pi(pose_i[0], pose_i[1], pose_i[2]), pj(pose_j[0], pose_j[1], pose_j[2]);
    const Q qi(pose_i[6], pose_i[3], pose_i[4], pose_i[5]);
    const Q qj(pose_j[6], pose_j[3], pose_j[4], pose_j[5]);
    const V3 vi(sb_i[0], sb_i[1], sb_i[2]), vj(sb_j[0], sb_j[1], sb_j[2]);
    const V3 bai(sb_i[3], sb_i[4], sb_i[5]), bgi(sb_i[6], sb_i[7], sb_i[8]);
    const V3 baj(sb_j[3], sb_j[4], sb_j[5]), bgj(sb_j[6], sb_j[7], sb_j[8]);
    const V3 dba = bai - pre_.biasLin().acc.cast<T>();
    const V3 dbg = bgi - pre_.biasLin().gyro.cast<T>();
    const T dt = T(pre_.dt());
    const V3 g = g_.cast<T>();

    // Bias-corrected rotation increment, ΔR Exp(dR/dbg δbg), as a quaternion.
    const V3 phi = pre_.dR_dbg().cast<T>() * dbg;
    T aa[3] = {phi[0], phi[1], phi[2]}, qc[4];
    ceres::AngleAxisToQuaternion(aa, qc);  // w x y z
    const Q dq = dR_q_.cast<T>() * Q(qc[0], qc[1], qc[2], qc[3]);
    const Q qe = dq.conjugate() * qi.conjugate() * qj;
    T qe_wxyz[4] = {qe.w(), qe.x(), qe.y(), qe.z()}, rR[3];
    ceres::QuaternionToAngleAxis(qe_wxyz, rR);

    const Eigen::Matrix<T, 3, 3> RiT = qi.conjugate().toRotationMatrix();
    const V3 dv = pre_.deltaV().cast<T>() + pre_.dv_dba().cast<T>() * dba + pre_.dv_dbg().cast<T>() * dbg;
    const V3 dp = pre_.deltaP().cast<T>() + pre_.dp_dba().cast<T>() * dba + pre_.dp_dbg().cast<T>() * dbg;
    const V3 rv = RiT * (vj - vi - g * dt) - dv;
    const V3 rp = RiT * (pj - pi - vi * dt - T(0.5) * g * dt * dt) - dp;

    Eigen::Matrix<T, 15, 1> r;
    r << rR[0], rR[1], rR[2], rv, rp, baj - bai, bgj - bgi;
    Eigen::Map<Eigen::Matrix<T, 15, 1>> out(res);
    out = sqrt_info_.cast<T>() * r;
    return true;
}

}  // namespace superloc::fusion
