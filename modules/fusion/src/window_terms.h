// The IMU window's factors evaluated one by one, without a Ceres problem, and the current
// state's information from the window's (internal to the fusion module: frame_problem.cpp's solve
// and window_information.cpp's information share them).
#pragma once

#include <ceres/ceres.h>
#include <superloc/fusion/frame_problem.h>

#include <memory>
#include <optional>
#include <vector>

namespace superloc::fusion::detail {

/// The window's information over [prev pose, prev speed-bias, cur pose, cur speed-bias]
/// (tangent coordinates: map-frame translation, body rotation increment). SolveSummary::marginal
/// is its Gauss-Newton form at the solution with the previous state eliminated (Schur
/// complement), in StatePriorFactor's error coordinates (translation in the reference's body axes).
using Mat30d = Eigen::Matrix<double, 30, 30>;

/// The current state's information M (15 x 15, in the window's tangent coordinates) in
/// StatePriorFactor's error coordinates (translation in the body axes of the reference), as a
/// StatePrior at cur.
std::optional<StatePrior> asStatePrior(Mat15d M, const FrameState& cur);

/// The current state's StatePrior of the window's information H, the previous state
/// eliminated (Schur complement).
std::optional<StatePrior> marginalizeInformation(const Mat30d& H, const FrameState& cur);

/// One factor of the window and the blocks it reads (0 prev pose, 1 prev speed-bias, 2 cur
/// pose, 3 cur speed-bias).
struct WindowTerm {
    std::unique_ptr<ceres::CostFunction> f;
    std::vector<int> blocks;
    const ceres::LossFunction* loss = nullptr;  ///< not owned; the solve applies it, the information does not
};

/// A term's residual (at most kMaxTermResiduals) and Jacobian in the window's tangent columns.
constexpr int kMaxTermResiduals = 15;
using TermResidual = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxTermResiduals, 1>;
using TermJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxTermResiduals, 30>;

/// Term t's residual r at the blocks (0 prev pose, 1 prev speed-bias, 2 cur pose, 3 cur
/// speed-bias) and, when J is not null, its Jacobian over `cols` tangent columns: block b's at
/// col[b] (col[b] < 0: the block is held, no columns), a pose's ambient columns times
/// PoseManifold's PlusJacobian, as Ceres does. No loss applied. False when the factor fails.
bool evaluateTerm(const WindowTerm& t, const double* const block[4], const int col[4], int cols, TermResidual& r,
                  TermJacobian* J);

/// The factors' Jacobian over the window (30 tangent columns, as windowJacobian's), evaluated
/// factor by factor without building a Ceres problem (no losses: the window's factors have
/// none); each pose block's ambient columns times PoseManifold's PlusJacobian, as Ceres does.
std::optional<Eigen::Matrix<double, Eigen::Dynamic, 30>> directWindowJacobian(const std::vector<WindowTerm>& terms,
                                                                             FrameState& prev, FrameState& cur);

/// The IMU window's factors: the IMU factor and the previous state's prior (in.prev_prior, else
/// the fixed sigmas), as addImuWindow adds them to a problem.
std::vector<WindowTerm> imuWindowTerms(const FrameProblemInputs& in, const FusionParams& params, const FrameState& prev);

}  // namespace superloc::fusion::detail
