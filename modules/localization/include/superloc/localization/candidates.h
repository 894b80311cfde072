// Multi-frame hypothesis tracking (doc/relocalization.md §4): one scan cannot tell look-alike
// places apart (the simulated office's rooms fit within 1-8 % of each other), several scans
// along the motion can. The candidates of an ambiguous relocalization of a frame without a pose
// are each carried by the measured motion, verified on every scan as a hypothesis, and their
// evidence (summed inlier ratio) accumulated; one is committed only when it is clearly best.
#pragma once

#include <mrpt/system/COutputLogger.h>
#include <superloc/localization/health.h>
#include <superloc/localization/localizer_params.h>
#include <superloc/localization/tracker.h>
#include <superloc/localization/verify.h>

#include <array>
#include <string>
#include <vector>

namespace superloc::localization {

class CandidateTracker {
   public:
    CandidateTracker(const LocalizerParams& params, const Verifier& verifier, const SensorHistory& sensors,
                     const mrpt::system::COutputLogger& log)
        : params_(params), verifier_(verifier), sensors_(sensors), log_(log) {}

    bool empty() const { return set_.empty(); }
    /// Frames the set has been tracked.
    int age() const { return age_; }
    /// The reports of the candidates (rivals of a search's winner: it must beat them too).
    std::vector<const FrameReport*> reports() const;

    /// First half, on each scan of a frame without a pose (`rep`, its report): each candidate
    /// moved by the measured motion since its frame and verified from there (Verifier, judged by
    /// `judge`); those lost or fitting clearly worse than the run's reference are dropped, those
    /// that met merged. Returns the time it took [ms].
    double refine(Frame& f, const FrameReport& rep, const HealthJudge& judge);
    /// After an ambiguous search on such a frame: its attempts that stand (best first, not
    /// already tracked, not clearly worse than the best tracked) join the set while it has room.
    /// Returns the number of candidates.
    int admit(std::vector<Attempt> standing, const std::string& trigger);
    /// Second half, after this frame's search (if any: `searched`, what it did) merged its
    /// hypotheses: the best candidate clearly and consistently best over the frames is committed
    /// (Accepted: the decision takes its pose); else the frame is reported lost with the best
    /// candidate's pose (Ambiguous), or Failed when none is left.
    RecoveryDecision decide(Frame& f, const FrameReport& rep, const RelocReport& searched, const HealthJudge& judge);
    void clear() { set_.clear(); }

   private:
    /// A pose of an ambiguous relocalization, tracked over the following scans.
    struct Candidate {
        fusion::FrameState state;       ///< at its last frame (time state.t)
        bool has_velocity = false;      ///< state's velocity measured by the IMU over a tracked frame
        std::optional<SE3d> T_map_imu_before;  ///< its pose one frame earlier (constant velocity)
        double t_before = 0;
        double evidence = 0;            ///< summed inlier ratio over its frames
        int frames = 0;                 ///< frames of evidence (the search's included)
        std::vector<double> history;    ///< inlier ratio per frame, the latest last
        bool ruled_out = false;         ///< judged against the best on the last decision
        /// per translation axis: constrained by the scan (gamma >= weak_gamma) on one of its
        /// frames, every frame since moved by measured motion (IMU or odom_alt), which carries it
        std::array<bool, 3> axis_held{};
        FrameReport rep;                ///< its last frame's fit
        HealthChecks checks;            ///< ... and the health checks on it
        std::vector<Correspondence> corr;  ///< its last frame's association
        AssociationStats stats;
    };
    /// Whether each translation the candidate's scan constrains weakly is held all the same:
    /// probes moved along it come back or fit clearly worse.
    bool weakAxesHeld(Frame& f, const Candidate& c, const HealthJudge& judge);

    const LocalizerParams& params_;
    const Verifier& verifier_;
    const SensorHistory& sensors_;
    const mrpt::system::COutputLogger& log_;
    std::vector<Candidate> set_;  ///< the candidates being tracked (none: empty)
    std::string trigger_;         ///< the trigger of the search that gave the candidates
    int age_ = 0;                 ///< frames the set has been tracked
    double track_ms_ = 0;         ///< [ms] refine() on this frame
    int dropped_ = 0, over_budget_ = 0;  ///< ...candidates it dropped, left out
    bool left_out_ = false;       ///< a hypothesis of this frame's search found the set full
    int judged_ = 0;              ///< candidates of this set dropped (lost, bad fit, ruled out)
    /// frames on which a search proposed another place (standing: not lost) that fit clearly
    /// worse than the best tracked candidate (under track_ratio x its inlier ratio)
    int outranked_frames_ = 0;
};

}  // namespace superloc::localization
