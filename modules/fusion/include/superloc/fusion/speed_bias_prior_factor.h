// SpeedBiasPriorFactor: prior on a speed-bias block (velocity, accelerometer bias, gyro bias):
// r = diag(sqrt_info) (x - x_ref).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <superloc/core/types.h>

namespace superloc::fusion {

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
