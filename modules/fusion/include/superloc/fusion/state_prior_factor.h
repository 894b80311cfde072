// StatePriorFactor: a Gaussian prior on a whole frame state (pose and speed-bias block) with a
// full 15x15 square-root information, correlations included: the previous frame's state as the
// last solve left it, marginalised (solveFrame's SolveSummary::marginal; doc/method.md §3).
// Residual r = L [toVec6(T_ref^-1 T) ; sb - sb_ref], order (x y z roll pitch yaw, v, b_a, b_g).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <superloc/core/types.h>
#include <superloc/fusion/relative_error.h>

namespace superloc::fusion {

using Vec9d = Eigen::Matrix<double, 9, 1>;
using Mat15d = Eigen::Matrix<double, 15, 15>;

/// A frame state's Gaussian: mean (T_ref, sb_ref) and square-root information in the error
/// coordinates of StatePriorFactor (translation in the T_ref body axes, rotation as a right
/// increment, then velocity and biases).
struct StatePrior {
    SE3d T_ref = SE3d::Identity();
    Vec9d sb_ref = Vec9d::Zero();
    Mat15d sqrt_info = Mat15d::Zero();
};

struct StatePriorFactor {
    explicit StatePriorFactor(const StatePrior& p) : p_(p), qr_(p.T_ref.linear()) {}
    template <typename T>
    bool operator()(const T* pose, const T* sb, T* res) const {
        const Eigen::Quaternion<T> q(pose[6], pose[3], pose[4], pose[5]);
        const Eigen::Matrix<T, 3, 1> t(pose[0], pose[1], pose[2]);
        Eigen::Matrix<T, 15, 1> e;
        detail::relativeError<T>(p_.T_ref.translation().cast<T>(), qr_.cast<T>(), t, q, e.data());
        for (int k = 0; k < 9; ++k) e[6 + k] = sb[k] - T(p_.sb_ref[k]);
        Eigen::Map<Eigen::Matrix<T, 15, 1>> out(res);
        out = p_.sqrt_info.cast<T>() * e;
        return true;
    }
    /// The factor the solves use: its Jacobians written out (state_prior_factor.cpp; test
    /// StatePriorFactor.AnalyticJacobiansAreTheAutodiffOnes).
    static ceres::CostFunction* Create(const StatePrior& p);
    /// The same residual differentiated with dual numbers (the test's reference).
    static ceres::CostFunction* CreateAutoDiff(const StatePrior& p) {
        return new ceres::AutoDiffCostFunction<StatePriorFactor, 15, 7, 9>(new StatePriorFactor(p));
    }
    StatePrior p_;
    Eigen::Quaterniond qr_;
};

}  // namespace superloc::fusion
