// The one verification every recovery policy uses (recovery.h): a pose tried for the current
// scan is solved by the solve function it is given (the Tracker's registration from there,
// Tracker::solveFrom), then judged by the health checks it is handed for the frame (HealthJudge:
// a value; nothing of the run is touched).
#pragma once

#include <superloc/localization/health.h>
#include <superloc/localization/relocalization.h>
#include <superloc/localization/tracker.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace superloc::localization {

/// A pose tried for the current scan and what came of it.
struct Attempt {
    FrameReport rep;     ///< the report it was verified from, with its solve's (sol.report)
    FrameSolution sol;
    Verdict verdict;     ///< the health checks on it
};

/// The frame's pose as it stands when a Recovery policy looks at it (read only): its solution,
/// its report and the health checks' verdict on it.
struct OwnPose {
    const FrameSolution& sol;
    const FrameReport& rep;
    const Verdict& verdict;
};

/// What a Recovery policy decided for the current frame, as a value: Localizer::process applies
/// it (the only code that changes the frame's report): a pose taken is judged afresh, then the
/// evidence is handed to the health checks in order.
struct RecoveryDecision {
    RelocOutcome outcome = RelocOutcome::None;
    /// A verified pose replaces the frame's own solve: its solution, whose report is the solve's
    /// (the frame keeps its own times). Empty: the frame's own stands.
    std::optional<FrameSolution> taken;
    bool recovered = false;  ///< ...taken as a relocalization (FrameReport::recovered)
    /// ...keeping the frame's own verdict instead of being judged afresh (the start check's tie:
    /// the own solve's doubt stands, and the search that follows settles it)
    bool keep_verdict = false;
    /// Nothing taken, the frame lost all the same, reporting the best pose found (an ambiguous
    /// search's, or the best candidate's).
    struct Shown {
        SE3d T_map_lidar, T_map_imu;
    };
    std::optional<Shown> shown;
    std::optional<RelocReport> reloc;      ///< what the policy did (frames.csv reloc_*), when one ran
    double ms = 0;                         ///< [ms] its search, verification and candidate tracking
    std::vector<HealthEvidence> evidence;  ///< for the health checks (HealthJudge::amend)
    bool restart = false;                  ///< the next frame starts with its velocity unknown
};

/// How a pose is solved for the current scan: the Tracker's registration from `start`
/// (Tracker::solveFrom), its report `base` with the solve's fields.
using SolveFn =
    std::function<FrameSolution(Frame& f, const fusion::FrameState& start, VerifyAs as, const TrackReport& base)>;

class Verifier {
   public:
    Verifier(SolveFn solve, const RelocalizationParams& params) : solve_(std::move(solve)), params_(params) {}
    /// The frame solved from `start` (at the scan's time) as `as` says, on a copy of `base`,
    /// and judged by `judge`.
    Attempt verify(Frame& f, const fusion::FrameState& start, const FrameReport& base, VerifyAs as,
                   const HealthJudge& judge) const;
    /// Each pose (T_map_lidar) in turn, from a state at rest with the frame's previous biases.
    std::vector<Attempt> verify(Frame& f, const std::vector<SE3d>& poses, const FrameReport& base, VerifyAs as,
                                const HealthJudge& judge) const;
    /// Verified: settled, and fitting as tracking fits on this map (no inlier flag against the
    /// run's reference; with none yet, at least accept_inlier_ratio). A pose that fits clearly
    /// worse may stand as an alternative but is not taken (campus kidnap: a pose 9.4 m off,
    /// inlier ratio under 0.9 x the reference, was taken when the right one was outside the
    /// region).
    bool fits(const FrameReport& rep, const Verdict& v) const;
    bool fits(const Attempt& a) const { return fits(a.rep, a.verdict); }

   private:
    SolveFn solve_;
    const RelocalizationParams& params_;
};

}  // namespace superloc::localization
