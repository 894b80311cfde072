// The Recovery (doc/health.md step 7, doc/relocalization.md): what the Localizer does when a
// frame's own solve is in question. Every caller proposes poses and verifies them the same way
// (Verifier, verify.h: the Tracker's registration from each pose, then the health checks); each has its own
// small policy for what to propose and what to take:
//   start check  (start_check.cpp)  seeds around a given initial pose; the frame's own solve is
//                                   one of the rivals; a tie keeps the own solve (degraded)
//   search       (lost_search.cpp)  the global search's hypotheses, for a frame lost, in doubt,
//                                   or without a pose; a tie keeps candidates to track
//   candidates   (candidates.h)     the candidates of an ambiguous search, each moved by the
//                                   measured motion and verified on every scan until one is
//                                   clearly best
// A policy is handed the frame's pose as it stands (OwnPose: solution, report, verdict) and the
// frame's health checks (HealthJudge, a value), and returns a RecoveryDecision (verify.h): the
// pose taken if any, what its search did, the evidence for the health checks, whether the next
// frame restarts. Localizer::process applies it; the Recovery changes no report and sets no
// health, and holds neither the Tracker nor the HealthMonitor.
#pragma once

#include <mrpt/system/COutputLogger.h>
#include <superloc/localization/candidates.h>
#include <superloc/localization/health.h>
#include <superloc/localization/localizer_params.h>
#include <superloc/localization/tracker.h>
#include <superloc/localization/verify.h>
#include <superloc/reloc/global_search.h>

#include <optional>
#include <string>
#include <vector>

namespace superloc::localization {

class Recovery {
   public:
    /// `solve`: the frame solved from a pose (Tracker::solveFrom).
    Recovery(const LocalizerParams& params, SolveFn solve, const SensorHistory& sensors,
             const mrpt::system::COutputLogger& log);
    /// The global search over the map in use (none: relocalization disabled).
    void setSearch(const reloc::GlobalSearch* search) { search_ = search; }

    /// The next scan is localized without a pose (Localizer::relocalize).
    void relocalize(const std::optional<reloc::SearchRegion>& region);
    /// Whether the current frame has no pose of its own: a relocalization was asked for, or
    /// candidates are tracked.
    bool requested() const { return pending_ || !candidates_.empty(); }
    /// A relocalization is still asked for (no pose accepted yet).
    bool pending() const { return pending_; }

    /// A frame without a pose (requested()): its candidates tracked, the map searched; the
    /// accepted pose, or nothing (the frame lost, reporting the best pose).
    RecoveryDecision withoutPose(Frame& f, const OwnPose& own, const HealthJudge& judge);
    /// The first frame from a given pose `T0` (start_check.cpp, doc/health.md "Start").
    RecoveryDecision checkStart(Frame& f, const SE3d& T0, const OwnPose& own, const HealthJudge& judge);
    /// Step 7: a frame lost for a while, or in doubt, searches the map (when `may_search`), and
    /// the doubt carried to the next frames is updated.
    RecoveryDecision recoverIfLost(Frame& f, bool may_search, const OwnPose& own, const HealthJudge& judge);
    /// What the next frame starts from, decided when the frame is final.
    struct NextFrame {
        fusion::FrameState state;  ///< the frame's own, or a lost frame's restart from the last one not lost
        bool restart = false;      ///< its velocity is unknown (Tracker::end)
    };
    /// The frame is final (`restart`: its decisions said the next frame restarts): the last
    /// frame not lost is updated, and the next frame's start decided.
    NextFrame endFrame(const Frame& f, const fusion::FrameState& state, const FrameReport& rep, bool restart);

   private:
    /// The map searched for the current scan (lost_search.cpp), in `region` or everywhere.
    RecoveryDecision search(Frame& f, const reloc::SearchRegion* region, const OwnPose& own, const HealthJudge& judge);
    /// The start check's seeds solved as hypotheses: one pose per basin they reach that fits
    /// within start_refine_ratio of the best, best first (start_check.cpp).
    std::vector<SE3d> startBasins(Frame& f, const std::vector<SE3d>& seeds, const FrameReport& rep,
                                  const HealthJudge& judge);
    /// `best` replaces the frame's own solve `own` (both policies): its velocity carried over
    /// when the frame was tracked, and whether the next frame starts with its velocity unknown.
    void accept(const Frame& f, const Attempt& own, const Attempt& best, RelocReport& rr, RecoveryDecision& d);
    /// The attempts that fit (verified, verify.h) and those not lost (standing), in order.
    void sortOut(std::vector<Attempt>&& attempts, std::vector<Attempt>& verified, std::vector<Attempt>& standing) const;
    /// Once a policy's attempts are verified: false when none was (`d` reports "verification"
    /// with the policy's times), else true with `verified` best first (highest inlier ratio).
    bool rank(std::vector<Attempt>& verified, RelocReport& rr, RecoveryDecision& d) const;
    /// What a policy did, into its decision: `rr`, its outcome, and its search and verification
    /// times.
    static void report(const RelocReport& rr, RecoveryDecision& d);
    /// `o` explains the scan about as well as `best` (ambiguity_ratio x its inlier ratio) from
    /// another place (`start`: another basin of the start check, start_distinct_*).
    bool rival(const FrameReport& best, const FrameReport& o, bool start) const;
    /// Where a frame lost `lost_run` frames in a row searches: around the last frame not lost
    /// (local), or nowhere in particular (global: empty).
    std::optional<reloc::SearchRegion> lostRegion(double t, int lost_run) const;

    const LocalizerParams& params_;
    const SensorHistory& sensors_;
    const mrpt::system::COutputLogger& log_;
    const reloc::GlobalSearch* search_ = nullptr;
    Verifier verifier_;
    CandidateTracker candidates_;
    bool pending_ = false;  ///< relocalize() was called: the next scan searches
    std::optional<reloc::SearchRegion> region_;
    int lost_run_ = 0;      ///< consecutive lost frames
    /// The last frame not lost: where a local search looks, and where tracking restarts.
    struct GoodFrame {
        fusion::FrameState state;  ///< its state (time state.t)
        SE3d T_map_lidar;
    };
    std::optional<GoodFrame> last_good_;
    /// every frame since the last `ok` one was predicted by the IMU (the doubt guard trusts it)
    bool imu_chain_ = true;
    bool doubt_ = false;  ///< a frame in doubt was not settled by a search: confirm the next
    /// the scan time of the last search of a frame only in doubt that confirmed the frame's own
    /// pose (doubt_search_period); reset by a search that moved it
    std::optional<double> confirmed_t_;
    /// the last frame was `ok` or a verified relocalization: its pose can anchor a velocity
    bool prev_verified_ = false;
};

}  // namespace superloc::localization
