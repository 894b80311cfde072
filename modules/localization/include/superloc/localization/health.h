// Health of a localized frame (doc/health.md): ok | degraded | lost, from
// evidence that needs no ground truth. The point is never to be confidently wrong: a frame is
// `ok` only when every check passes.
//   lost      the registration failed (diverged: too few inliers, no correspondences, solver, a
//             jump without IMU to fall back on), or its inlier ratio fell below
//             lost_inlier_drop x what this map and sensor give when tracking is right
//   degraded  the pose stands but is not good enough to act on, or some evidence is missing: its
//             covariance's std above max_sigma_xyz / max_sigma_deg (what a navigation stack
//             tolerates), still moving when its rounds ran out, an inlier ratio below
//             degraded_inlier_drop x the reference, the IMU prediction disagreeing with the
//             solved pose, or a registration rejected in favour of the IMU prediction
//   ok        none of the above
// An axis the scan constrains weakly (gamma below weak_gamma) is reported (weak_axes) but is not
// degraded by itself: the IMU or odom_alt may hold it, and the covariance says whether they do.
// The reference inlier ratio is the median of the last `reference_frames` frames that were
// tracked (converged, not diverged, inliers and prediction checks passed).
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Core>

#include <array>
#include <deque>
#include <string>

namespace superloc::localization {

struct FrameReport;

enum class Health { Ok, Degraded, Lost };

/// Why a frame's registration was not taken (FrameReport::diverged_reason; frames.csv spells it
/// with divergenceName).
enum class Divergence {
    None,
    Inliers,            ///< inlier ratio below [localization] min_inlier_ratio
    Jump,               ///< solved pose too far from the prediction (no IMU to fall back on)
    JumpRejected,       ///< ... and the IMU prediction was kept instead (degraded, not lost)
    NoCorrespondences,  ///< nothing to register against
    Solver,             ///< the solver failed or gave a non-finite pose
    NoPose,             ///< localized without a pose (relocalize(), or candidates tracked)
};
/// "", "inliers", "jump", "jump_rejected", "no_correspondences", "solver", "no_pose"
const char* divergenceName(Divergence d);

/// The checks behind a frame's health, one flag each (health_reason spells them out).
struct HealthChecks {
    bool diverged = false;       ///< the registration failed (lost)
    bool jump_rejected = false;  ///< the IMU prediction was kept instead of the registration
    bool inliers_lost = false;   ///< inlier ratio below lost_inlier_drop x the reference (lost)
    bool inliers = false;        ///< inlier ratio below degraded_inlier_drop x the reference
    bool not_converged = false;  ///< still moving when the rounds ran out
    std::array<bool, 6> weak{};  ///< gamma below weak_gamma, per axis (reported, not degraded by itself)
    bool sigma_xyz = false;      ///< the position's std above max_sigma_xyz
    bool sigma_rot = false;      ///< the rotation's std above max_sigma_deg
    bool dead_reckoning = false; ///< a weak translation axis held by nothing measured too long
    bool prediction = false;     ///< IMU prediction and solved pose disagree
    bool drift = false;          ///< the solved rotation drifted from the gyro's over drift_window
    bool unconfirmed = false;    ///< after an unsettled doubt, not yet confirmed by a search

    /// The fit is clearly worse than tracking gives on this map.
    bool badFit() const { return inliers || inliers_lost; }
    /// The registration itself is in question (not only an axis the scan leaves open).
    bool inDoubt() const { return badFit() || not_converged; }
    bool weakTranslation() const { return weak[0] || weak[1] || weak[2]; }
};
const char* healthName(Health h);  ///< "ok", "degraded", "lost"

/// What the rest of the Localizer knows of a frame beyond its registration's report, handed to
/// the health checks (HealthJudge::amend), which alone decide what it makes of the frame's health.
/// (A frame without a pose is lost by its report alone: Divergence::NoPose.)
enum class HealthEvidence {
    Unconfirmed,     ///< after a doubt no search settled: the frame waits for a search to confirm it
    Confirmed,       ///< a search found nothing better around an unconfirmed frame
    StartAmbiguous,  ///< the start check found another pose that fits about as well
};

/// What the health checks make of one report: its state, the checks that failed ('+'-joined,
/// frames.csv health_reason) and as flags, and the reference inlier ratio it was judged against.
struct Verdict {
    Health health = Health::Ok;
    std::string reason;
    HealthChecks checks;
    double inlier_reference = 0;  ///< the run's reference before this frame (0: none yet)
};

/// Section [health] of the INI.
struct HealthParams : public mrpt::config::CLoadableOptions {
    double weak_gamma = 0.3;            ///< [-] an axis with gamma below: weak (reported; the risk flag is 0.2)
    /// The pose's covariance (FrameReport::cov): its largest std above these is degraded, what
    /// a navigation stack does not tolerate (doc/health.md)
    double max_sigma_xyz = 0.10;        ///< [m]
    double max_sigma_deg = 1.0;         ///< [deg]
    /// A translation axis the scan holds weakly and odom_alt does not hold (its per-frame std along
    /// it above max_sigma_xyz / 10) is carried by the prediction alone (the IMU chain, or constant
    /// velocity): beyond this long, degraded whatever the covariance says (doc/health.md: the IMU
    /// chain's std was measured overconfident on a corridor where the solver learned a wrong bias)
    double max_dead_reckoning_s = 3.0;  ///< [s]
    double degraded_inlier_drop = 0.9;  ///< [-] inlier ratio below this x the reference: degraded
    double lost_inlier_drop = 0.6;      ///< [-] below this x the reference: lost
    int reference_frames = 20;          ///< tracked frames whose median inlier ratio is the reference
    int reference_min_frames = 3;       ///< the relative checks start with this many
    /// A frame that ran out of rounds counts as not converged when its last update was above
    /// these (or it never reached the voxel map's finest level); below, it was only settling.
    double settled_xyz = 0.01;          ///< [m]
    double settled_deg = 0.1;           ///< [deg]
    double max_pred_xyz = 0.3;          ///< [m] IMU-predicted vs solved position farther: degraded
    double max_pred_deg = 3.0;          ///< [deg] the same for the rotation
    /// A slow drift the per-frame prediction check cannot see (a tilt on stairs, doc/health.md):
    /// the solved rotation against the gyro's over the last drift_window seconds of IMU-predicted
    /// frames. 0 turns it off.
    double drift_window = 1.0;          ///< [s]
    double max_drift_deg = 1.5;         ///< [deg] farther: degraded

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
};

/// The health checks as they stand for the current frame: the parameters and the run's
/// reference inlier ratio before it (HealthMonitor::judge). A value: judging a report, or
/// amending a verdict, changes nothing, so the Recovery judges its attempts with it and holds no
/// HealthMonitor.
class HealthJudge {
   public:
    HealthJudge(const HealthParams& p, double reference) : p_(&p), reference_(reference) {}
    /// The checks on a report's fields (diverged, converged, gamma, inlier_ratio, pred_dxyz /
    /// pred_ddeg as measured: FrameReport::measurePrediction, used_imu, cov, imu_drift_deg).
    Verdict operator()(const FrameReport& rep) const;
    /// What the evidence makes of a verdict: Unconfirmed an `ok` frame degraded ("unconfirmed"),
    /// Confirmed back to `ok`; StartAmbiguous an `ok` frame degraded ("start_ambiguous").
    Verdict amend(Verdict v, HealthEvidence e) const;
    /// The reference inlier ratio, 0 while fewer than reference_min_frames were tracked.
    double reference() const { return reference_; }
    const HealthParams& params() const { return *p_; }

   private:
    HealthChecks check(const FrameReport& r) const;
    /// Ran out of rounds while still moving (HealthParams::settled_xyz / settled_deg).
    bool notConverged(const FrameReport& r) const;
    const HealthParams* p_;
    double reference_;
};

/// Keeps what the health checks learn of this run, frame by frame: the reference inlier ratio
/// and the drift check's chain. Each frame is judged by the judge() it hands out (a value) and
/// committed once with its final report.
class HealthMonitor {
   public:
    explicit HealthMonitor(const HealthParams& p = {}) : p_(p) {}
    /// The checks for the current frame, against the run's reference as it stands.
    HealthJudge judge() const { return HealthJudge(p_, reference()); }
    /// The reference inlier ratio, 0 while fewer than reference_min_frames were tracked.
    double reference() const;
    const HealthParams& params() const { return p_; }

    /// The drift check's measure for a solved frame (FrameReport::imu_drift_deg): [deg] its
    /// rotation against the one the gyro carries along the chain of recorded frames over the
    /// last drift_window; 0 when the chain does not span half of it or the frame has no IMU.
    double imuDrift(const FrameReport& rep) const;
    /// Once per frame, with its final report: the run's reference takes its inlier ratio when its
    /// fit was sound (not diverged, converged, no inlier, prediction or drift flag), and the drift
    /// check's chain is extended with it when `chained` (the IMU predicted it from the last
    /// recorded frame and its own registration solved it), else started again from it; a lost
    /// or diverged frame ends the chain. The only change to the monitor's state.
    void commit(const FrameReport& rep, bool chained);

   private:
    HealthParams p_;
    std::deque<double> tracked_;  ///< inlier ratios of the last tracked frames
    /// The drift check's chain, oldest first: each frame's solved R_map_lidar and the rotation
    /// the IMU predicted from the frame before.
    struct DriftSample {
        double t = 0;
        Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
        Eigen::Matrix3d dR_pred = Eigen::Matrix3d::Identity();
    };
    std::deque<DriftSample> drift_chain_;
};

}  // namespace superloc::localization
