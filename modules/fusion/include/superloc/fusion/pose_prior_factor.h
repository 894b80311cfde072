// PosePriorFactor: absolute pose prior e = toVec6(T_ref^-1 · T) with a 6x6 square-root
// information, residual order (x y z roll pitch yaw); e.g. the previous frame's pose in the
// two-state window (a stand-in for marginalisation), or NDT's pose loosely coupled with the IMU.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <superloc/core/types.h>
#include <superloc/fusion/relative_error.h>

namespace superloc::fusion {

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

}  // namespace superloc::fusion
