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
// A policy returns what came of it (RelocOutcome) and, when it takes a pose, the frame's new
// solution and report; it hands the HealthMonitor its evidence and never sets a health itself.
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
    /// `solve`: the frame solved from a pose (Tracker::solveFrom); `health`: read only (its
    /// classification and the reference), the Localizer commits each frame to it.
    Recovery(const LocalizerParams& params, SolveFn solve, const HealthMonitor& health, const SensorHistory& sensors,
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

    /// A frame without a pose (requested()): its candidates tracked, the map searched; `sol`
    /// and `rep` become the accepted pose's, or stay (the frame lost, reporting the best pose).
    void withoutPose(Frame& f, FrameSolution& sol, FrameReport& rep);
    /// The first frame from a given pose `T0` (start_check.cpp, doc/health.md "Start").
    void checkStart(Frame& f, const SE3d& T0, FrameSolution& sol, FrameReport& rep);
    /// Step 7: a frame lost for a while, or in doubt, searches the map (when `may_search`), and
    /// the doubt carried to the next frames is updated.
    void recoverIfLost(Frame& f, bool may_search, FrameSolution& sol, FrameReport& rep);
    /// Whether a pose this frame took (a relocalization, the start check's, candidates') means
    /// the next frame starts with its velocity unknown, as decided so far this frame.
    bool restart() const { return restart_; }
    /// What the next frame starts from, decided when the frame is final.
    struct NextFrame {
        fusion::FrameState state;  ///< the frame's own, or a lost frame's restart from the last one not lost
        bool restart = false;      ///< its velocity is unknown (Tracker::setRestart)
    };
    /// The frame is final: the last frame not lost is updated, and the next frame's start decided.
    NextFrame endFrame(const Frame& f, const fusion::FrameState& state, const FrameReport& rep);

   private:
    /// The map searched for the current scan (lost_search.cpp), in `region` or everywhere.
    RelocOutcome search(Frame& f, const reloc::SearchRegion* region, FrameSolution& sol, FrameReport& rep);
    /// The start check's seeds solved as hypotheses: one pose per basin they reach that fits
    /// within start_refine_ratio of the best, best first (start_check.cpp).
    std::vector<SE3d> startBasins(Frame& f, const std::vector<SE3d>& seeds, const FrameReport& rep);
    /// `best` replaces the frame's own solve `own` (both policies): its velocity carried over
    /// when the frame was tracked, and whether the next frame starts with its velocity unknown.
    void accept(const Frame& f, const Attempt& own, const Attempt& best, RelocReport& rr, FrameSolution& sol,
                FrameReport& rep);
    /// The attempts that fit (verified, verify.h) and those not lost (standing), in order.
    void sortOut(std::vector<Attempt>&& attempts, std::vector<Attempt>& verified, std::vector<Attempt>& standing) const;
    /// Once a policy's attempts are verified: false when none was (`rep` reports "verification"
    /// with the policy's times), else true with `verified` best first (highest inlier ratio).
    bool rank(std::vector<Attempt>& verified, const StageTimes& ms, RelocReport& rr, FrameReport& rep) const;
    /// What a policy did, into the frame's report: `rr`, and its search and verification times
    /// added to the frame's own (`ms`).
    static void report(const StageTimes& ms, const RelocReport& rr, FrameReport& rep);
    /// `o` explains the scan about as well as `best` (ambiguity_ratio x its inlier ratio) from
    /// another place (`start`: another basin of the start check, start_distinct_*).
    bool rival(const FrameReport& best, const FrameReport& o, bool start) const;
    /// Where a frame lost `lost_run` frames in a row searches: around the last frame not lost
    /// (local), or nowhere in particular (global: empty).
    std::optional<reloc::SearchRegion> lostRegion(double t, int lost_run) const;
    /// The health checks on a report that changed pose (its prediction check first).
    void assess(FrameReport& rep) const;

    const LocalizerParams& params_;
    const HealthMonitor& health_;
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
    /// the last frame was `ok` or a verified relocalization: its pose can anchor a velocity
    bool prev_verified_ = false;
    bool restart_ = false;  ///< this frame's decision: the next one starts with its velocity unknown
};

}  // namespace superloc::localization
