// The one verification every recovery policy uses (recovery.h): a pose tried for the current
// scan is solved by the solve function it is given (the Tracker's registration from there,
// Tracker::solveFrom), then judged by the health checks (HealthMonitor::classify: the run's
// reference is not touched).
#pragma once

#include <superloc/localization/health.h>
#include <superloc/localization/relocalization.h>
#include <superloc/localization/tracker.h>

#include <functional>
#include <string>
#include <vector>

namespace superloc::localization {

/// A pose tried for the current scan and what came of it.
struct Attempt {
    FrameReport rep;     ///< the report it was verified from, with its solve's (sol.report)
    FrameSolution sol;
    Health health = Health::Lost;  ///< the health checks on it
    HealthChecks checks;
    std::string why;     ///< the failed checks, '+'-joined
};

/// How a pose is solved for the current scan: the Tracker's registration from `start`
/// (Tracker::solveFrom), its report `base` with the solve's fields.
using SolveFn =
    std::function<FrameSolution(Frame& f, const fusion::FrameState& start, VerifyAs as, const TrackReport& base)>;

class Verifier {
   public:
    Verifier(SolveFn solve, const HealthMonitor& health, const RelocalizationParams& params)
        : solve_(std::move(solve)), health_(health), params_(params) {}
    /// The frame solved from `start` (at the scan's time) as `as` says, on a copy of `base`.
    Attempt verify(Frame& f, const fusion::FrameState& start, const FrameReport& base, VerifyAs as) const;
    /// Each pose (T_map_lidar) in turn, from a state at rest with the frame's previous biases.
    std::vector<Attempt> verify(Frame& f, const std::vector<SE3d>& poses, const FrameReport& base,
                                VerifyAs as) const;
    /// Verified: settled, and fitting as tracking fits on this map (no inlier flag against the
    /// run's reference; with none yet, at least accept_inlier_ratio). A pose that fits clearly
    /// worse may stand as an alternative but is not taken (campus kidnap: a pose 9.4 m off,
    /// inlier ratio under 0.9 x the reference, was taken when the right one was outside the
    /// region).
    bool fits(const FrameReport& rep, const HealthChecks& c, Health h) const;
    bool fits(const Attempt& a) const { return fits(a.rep, a.checks, a.health); }
    const HealthMonitor& health() const { return health_; }

   private:
    SolveFn solve_;
    const HealthMonitor& health_;
    const RelocalizationParams& params_;
};

}  // namespace superloc::localization
