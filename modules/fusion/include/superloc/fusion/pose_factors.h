// Pose factors with a 6x6 square-root information, residual order (x y z roll pitch yaw):
//
// RelativePoseFactor — the relative-pose prior of the paper (§III-C, eq. "e_ij^prior"):
//   e = toVec6( ΔT_meas^-1 · (T_i^-1 T_j) )   (translation, then rotation vector)
// where ΔT_meas is the body motion from i to j measured by the second odometry (odom_alt).
// Its information W = diag(max(0, 1 - γ)) · s comes from the alignment risk (issue 5); here it is
// whatever 6x6 sqrt-information the caller passes (zero rows switch directions off).
//
// PosePriorFactor — absolute prior e = toVec6(T_ref^-1 · T), e.g. the previous frame's pose
// in the two-state window (a stand-in for marginalisation).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>
#include <superloc/core/types.h>

namespace superloc::fusion {

namespace detail {
/// r = toVec6(A^-1 B) for poses A (given as t, q) and B, templated for autodiff.
template <typename T>
void relativeError(const Eigen::Matrix<T, 3, 1>& ta, const Eigen::Quaternion<T>& qa,
                   const Eigen::Matrix<T, 3, 1>& tb, const Eigen::Quaternion<T>& qb, T* r) {
    const Eigen::Quaternion<T> qai = qa.conjugate();
    const Eigen::Matrix<T, 3, 1> dt = qai * (tb - ta);
    const Eigen::Quaternion<T> dq = qai * qb;
    T wxyz[4] = {dq.w(), dq.x(), dq.y(), dq.z()};
    r[0] = dt[0], r[1] = dt[1], r[2] = dt[2];
    ceres::QuaternionToAngleAxis(wxyz, r + 3);
}
}  // namespace detail

struct RelativePoseFactor {
    RelativePoseFactor(const SE3d& delta_meas, const Mat6d& sqrt_info)
        : delta_(delta_meas), sqrt_info_(sqrt_info), qm_(delta_meas.linear()) {}

    template <typename T>
    bool operator()(const T* pose_i, const T* pose_j, T* res) const {
        using V3 = Eigen::Matrix<T, 3, 1>;
        using Q = Eigen::Quaternion<T>;
        const Q qi(pose_i[6], pose_i[3], pose_i[4], pose_i[5]);
        const Q qj(pose_j[6], pose_j[3], pose_j[4], pose_j[5]);
        const V3 ti(pose_i[0], pose_i[1], pose_i[2]), tj(pose_j[0], pose_j[1], pose_j[2]);
        // Estimated relative motion Δ_est = T_i^-1 T_j.
        const Q qd = qi.conjugate() * qj;
        const V3 td = qi.conjugate() * (tj - ti);
        const Q qm = qm_.cast<T>();
        const V3 tm = delta_.translation().cast<T>();
        Eigen::Matrix<T, 6, 1> r;
        detail::relativeError<T>(tm, qm, td, qd, r.data());
        Eigen::Map<Eigen::Matrix<T, 6, 1>> out(res);
        out = sqrt_info_.cast<T>() * r;
        return true;
    }

    static ceres::CostFunction* Create(const SE3d& delta_meas, const Mat6d& sqrt_info) {
        return new ceres::AutoDiffCostFunction<RelativePoseFactor, 6, 7, 7>(
            new RelativePoseFactor(delta_meas, sqrt_info));
    }

    SE3d delta_;
    Mat6d sqrt_info_;
    Eigen::Quaterniond qm_;
};

struct PosePriorFactor {
    PosePriorFactor(const SE3d& T_ref, const Mat6d& sqrt_info)
        : ref_(T_ref), sqrt_info_(sqrt_info), qr_(T_ref.linear()) {}

    template <typename T>
    bool operator()(const T* pose, T* res) const {
        using V3 = Eigen::Matrix<T, 3, 1>;
        const Eigen::Quaternion<T> q(pose[6], pose[3], pose[4], pose[5]);
        const V3 t(pose[0], pose[1], pose[2]);
        Eigen::Matrix<T, 6, 1> r;
        detail::relativeError<T>(ref_.translation().cast<T>(),
                                 qr_.cast<T>(), t, q, r.data());
        Eigen::Map<Eigen::Matrix<T, 6, 1>> out(res);
        out = sqrt_info_.cast<T>() * r;
        return true;
    }

    static ceres::CostFunction* Create(const SE3d& T_ref, const Mat6d& sqrt_info) {
        return new ceres::AutoDiffCostFunction<PosePriorFactor, 6, 7>(new PosePriorFactor(T_ref, sqrt_info));
    }

    SE3d ref_;
    Mat6d sqrt_info_;
    Eigen::Quaterniond qr_;
};

/// Prior on a speed-bias block: r = sqrt_info (x - x_ref).
struct SpeedBiasPriorFactor {
    using Vec9d = Eigen::Matrix<double, 9, 1>;
    SpeedBiasPriorFactor(const Vec9d& ref, const Vec9d& sqrt_info_diag) : ref_(ref), w_(sqrt_info_diag) {}

    template <typename T>
    bool operator()(const T* sb, T* res) const {
        for (int k = 0; k < 9; ++k) res[k] = T(w_[k]) * (sb[k] - T(ref_[k]));
        return true;
    }

    static ceres::CostFunction* Create(const Vec9d& ref, const Vec9d& sqrt_info_diag) {
        return new ceres::AutoDiffCostFunction<SpeedBiasPriorFactor, 9, 9>(
            new SpeedBiasPriorFactor(ref, sqrt_info_diag));
    }

    Vec9d ref_, w_;
};

}  // namespace superloc::fusion
