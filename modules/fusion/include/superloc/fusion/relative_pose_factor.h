// RelativePoseFactor: the relative-pose prior of the paper (§III-C, eq. "e_ij^prior"):
//   e = toVec6( ΔT_meas^-1 · (T_i^-1 T_j) )   (translation, then rotation vector)
// where ΔT_meas is the body motion from i to j measured by the second odometry (odom_alt).
// Its information W = diag(max(0, 1 - γ)) · s comes from the alignment risk (doc/method.md §2);
// here it is whatever 6x6 sqrt-information the caller passes (zero rows switch directions off).
// Residual order (x y z roll pitch yaw).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <superloc/core/types.h>
#include <superloc/fusion/relative_error.h>

namespace superloc::fusion {

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

}  // namespace superloc::fusion
