// Registration (steps 3-5 of a frame, doc/localizer.md): the scan's features aligned to the prior
// map from a start pose, with the IMU window and the odom_alt prior when they take part. One
// interface, two implementations: IcpRegistration (coarse-to-fine association + joint solve,
// icp_registration.h) and NdtRegistration (PCL's NDT, then the IMU window, ndt_registration.h).
// A solve returns its result (FrameSolution, its report included) and touches nothing else: the
// caller keeps the solution it takes.
#pragma once

#include <superloc/core/correspondence.h>
#include <superloc/fusion/estimate_information.h>
#include <superloc/fusion/pose_posterior.h>
#include <superloc/fusion/frame_problem.h>
#include <superloc/fusion/scan_factor.h>
#include <superloc/imu/preintegration.h>
#include <superloc/localization/association.h>
#include <superloc/localization/frame_report.h>
#include <superloc/localization/method_variant.h>
#include <superloc/localization/scan_features.h>
#include <superloc/map/prior_map.h>
#include <superloc/risk/alignment_risk.h>

#include <optional>
#include <vector>

namespace superloc::localization {

/// One solve's result for the current scan: the frame's own, or a pose tried by the recovery.
struct FrameSolution {
    fusion::FrameState state;          ///< the solved state (at the scan's time)
    std::vector<Correspondence> corr;  ///< its last association (the quality is measured on it)
    AssociationStats stats;
    /// The IMU window's marginal of this state, from the solve's last round (a tracked solve
    /// with IMU and window = marginalized): the next frame's prior on its previous state.
    std::optional<fusion::StatePrior> marginal;
    /// A tracked solve's fusion evidence (FrameFusion, frame_fusion.h): the scan's information
    /// above its noise floor (body axes), where the estimate without odom_alt and the scan alone
    /// were weak, and the estimate's information filter after this frame's prediction (it is
    /// committed when the frame is final).
    Mat6d scan_info = Mat6d::Zero();
    fusion::Weakness est_weak, scan_weak;
    std::optional<fusion::EstimateInformation> est_info;
    /// A tracked solve's odom_alt prior (when one entered it).
    std::optional<fusion::RelativePosePrior> prior;
    /// A tracked frame's posterior (fusion::PosePosterior), committed when the frame is final.
    std::optional<fusion::PosePosterior::Update> post;
    /// What the solve reports (risk, fusion, rounds, quality, covariance, times): the frame's
    /// report from steps 1-2 with this solve's fields written over it.
    TrackReport report;
};

/// What a solve is for. Track: this frame in the prior map (the method's registration, IMU
/// window, odom_alt). Hypothesis: a pose of the search or a candidate verified (ICP in the voxel
/// map whatever the tracking association, no IMU, no odom_alt). LastScan: the motion since the
/// last frame against its scan (the tracking association, no IMU, no odom_alt).
enum class SolvePurpose { Track, Hypothesis, LastScan };

/// What a tracked solve's odom_alt fusion does around the rounds (FrameFusion implements it).
class RoundFusion {
   public:
    virtual ~RoundFusion() = default;
    /// At the risk step (the first round; a wide frame's first round at the finest level too),
    /// with the round's correspondences associated at T_map_imu and their risk: the relative-pose
    /// prior of the rounds that follow. Records its evidence in `sol` (and its report).
    virtual std::optional<fusion::RelativePosePrior> prior(const std::vector<Correspondence>& corr,
                                                           const SE3d& T_map_imu, const risk::RiskReport& risk,
                                                           FrameSolution& sol) = 0;
    /// After a round's solve from T_round_start: the pose to keep (T_solved unless amended).
    virtual RoundAmend afterRound(const SE3d& T_round_start, const fusion::ScanFactor& scan, const SE3d& T_solved) = 0;
};

/// One solve's inputs. The start is FrameSolution::state of the solution passed to solve().
struct RegistrationProblem {
    const ScanFeatures* features = nullptr;
    const map::PriorMap* map = nullptr;
    SolvePurpose purpose = SolvePurpose::Track;
    /// Velocity unknown (first frame, restart, a gap, a hypothesis): a wide basin, more rounds.
    bool wide = false;
    /// The IMU window (purpose Track with IMU): the previous state, optimised with the current
    /// one (it holds the window's estimate after the solve), the preintegration between them,
    /// its prior (the last frame's marginal; null: fixed sigmas), and whether to marginalise.
    fusion::FrameState* prev = nullptr;
    const imu::Preintegration* imu = nullptr;
    const fusion::StatePrior* prev_prior = nullptr;
    bool marginalize = false;
    RoundFusion* fusion = nullptr;  ///< purpose Track: the odom_alt fusion (never null then)
    /// purpose Track, not wide: the motion prediction was confirmed on the last frame (the Tracker
    /// decides; nothing else sets it), so a round that barely moves the pose may end the kernel's
    /// annealing ([localization] settle_xyz)
    bool may_settle = false;
    /// purpose Track: the last frame was weak in translation ([association] points_below_gamma),
    /// so this one is associated without voxel planes from its first round (the Tracker decides;
    /// a frame not carried so still switches on its own risk, IcpRegistration::round)
    bool without_voxel_planes = false;
};

class Registration {
   public:
    virtual ~Registration() = default;
    /// What the Tracker does around this registration's solves (the only ways the two differ
    /// outside solve()).
    struct Traits {
        /// registers every deskewed voxel candidate (ScanFeatures::ndt_source), not the features
        bool all_candidates = false;
        /// coarse to fine: a frame of unknown velocity starts wide at the coarsest level and has
        /// its sweep velocity estimated with its pose (FrameReport::coarse_start)
        bool coarse_to_fine = true;
        /// its last correspondences are at the solved pose (else the frame's quality is measured
        /// on an association there)
        bool correspondences_at_solution = true;
        /// the joint solve (scan, IMU window, odom_alt prior) the pose covariance's filter
        /// follows; else the covariance is the scan's alone
        bool joint = true;
    };
    virtual Traits traits() const { return {}; }
    /// Solves from sol.state (the start, at the scan's time) and leaves in `sol` the solved
    /// state, this solve's last correspondences, their statistics and its marginal, and in
    /// sol.report the solve's fields (risk, rounds, iterations, convergence, divergence, times).
    virtual void solve(const RegistrationProblem& p, FrameSolution& sol) const = 0;
};

}  // namespace superloc::localization
