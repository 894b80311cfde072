// The per-frame joint optimisation (paper eq. 12): scan residuals + IMU preintegration factor
// between the previous and current states + the relative-pose prior, solved with Ceres (a
// problem with the scan factor alone by Ceres' Levenberg-Marquardt written out for the 6-D
// pose, frame_problem.cpp: no problem to build, the same steps).
#pragma once

#include <superloc/fusion/fusion_params.h>
#include <superloc/fusion/scan_factor.h>
#include <superloc/fusion/state.h>
#include <superloc/fusion/state_prior_factor.h>
#include <superloc/imu/imu_params.h>
#include <superloc/imu/preintegration.h>

#include <optional>

namespace superloc::fusion {

/// Relative motion of the body from the previous to the current frame measured by odom_alt,
/// with its 6x6 square-root information in (x y z roll pitch yaw) order (see relative_pose_factor.h).
struct RelativePosePrior {
    SE3d delta = SE3d::Identity();  ///< T_imu(prev)_imu(cur)
    Mat6d sqrt_info = Mat6d::Zero();
    /// The information odom_alt is worth over the frame, for the pose's covariance
    /// (PosePosterior), where the solve holds it on another scale (superloc with IMU); empty:
    /// sqrt_info's.
    std::optional<Mat6d> worth;
};

struct FrameProblemInputs {
    FrameState* prev = nullptr;   ///< previous frame (optimised only when `imu` is given)
    FrameState* cur = nullptr;    ///< current frame, initial guess in, estimate out
    ScanFactor* scan = nullptr;   ///< not owned; may be null (no scan constraint)
    const imu::Preintegration* imu = nullptr;  ///< between prev and cur, or null (no IMU)
    Vec3d g_map = Vec3d(0, 0, -9.81);
    double acc_bias_rw = 0.001, gyro_bias_rw = 0.0001;  ///< see ImuParams
    std::optional<RelativePosePrior> prior;
    /// Absolute prior on the current pose, e.g. a registration result from outside this
    /// problem (method=ndt fuses PCL's NDT pose with the IMU factor this way).
    std::optional<std::pair<SE3d, Mat6d>> cur_pose_prior;  ///< T_map_imu, 6x6 sqrt-information
    /// With `imu`: the previous state's prior, e.g. the last solve's marginal
    /// (SolveSummary::marginal); null = the fixed prev_*_sigma priors of FusionParams around
    /// the previous state's current values (fixedStatePrior).
    const StatePrior* prev_prior = nullptr;
    /// With `imu`: compute SolveSummary::marginal after the solve.
    bool marginalize = false;

    /// The IMU half, the same for every solve and the estimate: the preintegration between the
    /// states (or null), gravity from `p` (the map is z-up) and its bias random walks times
    /// `walk_scale` (the estimate's ActiveFusionParams::estimate_imu_scale; the solver's 1).
    void setImu(const imu::Preintegration* pre, const imu::ImuParams& p, double walk_scale = 1.0) {
        imu = pre;
        g_map = Vec3d(0, 0, -p.gravity);
        acc_bias_rw = walk_scale * p.acc_bias_rw;
        gyro_bias_rw = walk_scale * p.gyro_bias_rw;
    }
};

struct SolveSummary {
    bool usable = false;      ///< Ceres' IsSolutionUsable() (the scan-only path: its equivalent)
    int iterations = 0;
    double initial_cost = 0, final_cost = 0;
    /// The current state's marginal at the solution: the problem's information (Gauss-Newton,
    /// J^T J with the IRLS weights of the scan factor) with the previous state eliminated by its
    /// Schur complement, as a prior for the next frame's solve (its previous state). Only when
    /// asked (`marginalize`), with the IMU factor and a usable solution.
    std::optional<StatePrior> marginal;
};

/// The fixed-sigma prior on a state (FusionParams prev_*_sigma) around its values.
StatePrior fixedStatePrior(const FrameState& s, const FusionParams& params);

/// Builds and solves the problem once (the caller re-associates and calls again): Ceres'
/// Levenberg-Marquardt run step for step on the problem's normal equations, without building a
/// Ceres problem (the same steps to rounding as solveFrameWithCeres, FrameProblem.*MatchesCeres).
SolveSummary solveFrame(const FrameProblemInputs& in, const FusionParams& params);
/// The same problem built and solved by Ceres (SPARSE_NORMAL_CHOLESKY): the reference the tests
/// and the microbenchmark compare solveFrame with.
SolveSummary solveFrameWithCeres(const FrameProblemInputs& in, const FusionParams& params);

/// What the IMU window knows of the current state before its scan is seen: the previous state's
/// prior (`in.prev_prior`, else the fixed sigmas) carried through the IMU factor to the current
/// state at its present values (the prediction). 15 x 15 information in StatePriorFactor's error
/// coordinates (translation in the current body axes, body rotation, velocity, biases): the
/// pose block is in the coordinates of scanInformation (a right perturbation T Exp(d)). Empty
/// without IMU (`in.imu` null or dt 0) or when the linearization fails. Touches neither state;
/// the scan is not used; odom_alt's relative prior `in.prior`, when set, joins the two states
/// (without its robust loss) before the previous one is eliminated.
std::optional<Mat15d> imuWindowStateInformation(const FrameProblemInputs& in, const FusionParams& params);

/// The current state's information (as imuWindowStateInformation gives it) of an estimate that
/// weighed odom_alt's prior at `in.prior`'s sqrt_info (B_s) while it is worth `worth` (B_t),
/// without and with the scan's information `scan` on the current pose (body axes, as
/// scanInformation).
struct WeighedWindowInformation {
    Mat15d without_scan;
    Mat15d with_scan;
};
/// From the window's sandwich covariance H_s^-1 (H_rest + E^T B_s B_t^+ B_s E) H_s^-1 (E: the
/// prior's error Jacobian, H_rest: the IMU factor, the previous state's prior and, for
/// `with_scan`, the scan), its current-state block inverted. Equal to imuWindowStateInformation
/// with the prior at B_t when B_s = B_t; an overweighted odom_alt makes the estimate follow it
/// and its error be odom_alt's (the baselines' covariance, doc/method.md §4). The scan is inside
/// the sandwich: the solve weighed it against the overweighted odom_alt too, so its
/// information cannot be added afterwards. One Jacobian evaluation for both. Empty without
/// `in.prior` or IMU, or when the linearization fails.
std::optional<WeighedWindowInformation> imuWindowStateInformationWeighed(const FrameProblemInputs& in,
                                                                         const FusionParams& params,
                                                                         const Mat6d& worth, const Mat6d& scan);

/// The pose's information in a state information M (15 x 15, pose first): velocity and biases
/// eliminated by the Schur complement. Empty when their block is singular.
std::optional<Mat6d> poseInformation(const Mat15d& M);

}  // namespace superloc::fusion
