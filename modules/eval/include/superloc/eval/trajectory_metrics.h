// Trajectory accuracy (doc/evaluation.md): time association, ATE, RPE (delta = 1 frame).
#pragma once

#include <superloc/core/types.h>

#include <cstddef>
#include <utility>
#include <vector>

namespace superloc::eval {

/// Estimated frames paired with GT frames by nearest timestamp.
struct Association {
    /// (estimate index, GT index), in estimate order; one-to-one: a GT frame claimed by several
    /// estimates keeps the nearest in time (the earlier one on a tie).
    std::vector<std::pair<size_t, size_t>> pairs;
    /// For every estimate, its GT index or SIZE_MAX when it has none within the tolerance.
    std::vector<size_t> gt_of_est;
};

/// Pairs each estimate with the GT sample nearest in time when |dt| <= tolerance [s].
/// Both trajectories must be sorted by time (loadTum guarantees it).
Association associate(const Trajectory& est, const Trajectory& gt, double tolerance);

/// Summary of a list of errors (all zero for an empty list).
struct ErrorStats {
    size_t n = 0;
    double rmse = 0, mean = 0, median = 0, max = 0;
};
ErrorStats errorStats(std::vector<double> values);

/// Absolute trajectory error over the associated pairs.
struct AteResult {
    ErrorStats trans;                  ///< [m] |t_gt - t_est'|
    ErrorStats rot;                    ///< [rad] angle of R_gt^T R_est'
    SE3d T_gt_est = SE3d::Identity();  ///< alignment applied to the estimate (identity if none)
    std::vector<double> trans_errors;  ///< [m] per pair, in pair order
};

/// SE(3) alignment T_gt_est minimising sum |p_gt - T p_est|^2 (Umeyama 1991, no scale).
/// Identity for fewer than 3 pairs.
SE3d alignSE3(const Trajectory& est, const Trajectory& gt, const Association& a);

/// ATE; with `align` the estimate is first moved by alignSE3 (default: map frame, none).
AteResult computeAte(const Trajectory& est, const Trajectory& gt, const Association& a, bool align);

/// Relative pose error, delta = 1 frame, judged per estimated frame.
struct RpeResult {
    /// Per estimated frame i >= 1 (size est.size() - 1): the error of the step i-1 -> i,
    /// E = (G_{i-1}^-1 G_i)^-1 (P_{i-1}^-1 P_i) with G the associated GT poses; translation |t_E|
    /// [m] and rotation angle(E) [rad]; NaN when frame i-1 or i has no GT pair.
    std::vector<double> frame_trans, frame_rot;
    ErrorStats trans, rot;  ///< over the judged (finite) steps
};
RpeResult computeRpe(const Trajectory& est, const Trajectory& gt, const Association& a);

}  // namespace superloc::eval
