// The search policy of the Recovery (recovery.h, doc/health.md step 7): the global search
// proposes poses for the current scan (around the last pose not lost, or everywhere), each is
// verified, and one is taken only when nothing else explains the scan about as well and no
// translation of it is unconstrained (the paper's alignment risk: a corridor's scan fits
// everywhere along it). A tie on a frame without a pose keeps its poses as candidates.
#include <mrpt/core/format.h>
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/localization/recovery.h>

#include <algorithm>

namespace superloc::localization {
namespace {
using Clock = SteadyClock;
}  // namespace

RecoveryDecision Recovery::search(Frame& f, const reloc::SearchRegion* region, const OwnPose& own_pose,
                                  const HealthJudge& judge) {
    const auto& rp = params_.relocalization;
    const Scan& scan = *f.scan;
    const FrameReport& rep = own_pose.rep;
    const bool own_lost = own_pose.verdict.health == Health::Lost;
    RecoveryDecision d;
    RelocReport rr;
    rr.mode = region ? "local" : "global";
    rr.trigger = pending_ ? "request" : own_lost ? "lost" : "doubt";
    rr.outcome = RelocOutcome::Failed;
    // The frame's own solve, as it stands before the search.
    const Attempt own{rep, own_pose.sol, own_pose.verdict};

    // Gravity: the IMU-predicted attitude when there is one, else the search estimates it from
    // the scan's ground plane.
    auto t0 = Clock::now();
    std::optional<Mat3d> R_level;
    if (f.pred.used_imu)
        R_level = Mat3d((f.pred.T_map_imu * scan.T_imu_lidar).linear());
    else if (const auto R_level_imu =
                 params_.loc.use_imu ? sensors_.gravityAt(scan.t, params_.imu.gravity) : std::nullopt)
        R_level = Mat3d(*R_level_imu * scan.T_imu_lidar.linear());
    const reloc::GlobalSearchResult found = search_->search(scan.points, R_level, region);
    rr.hypotheses = static_cast<int>(found.hypotheses.size());
    if (found.hypotheses.empty()) {
        rr.search_ms = msSince(t0);
        rr.detail = "no_hypothesis" + (found.failure.empty() ? "" : ": " + found.failure);
        report(rr, d);
        return d;
    }
    // The best verify_hypotheses, and every other one the search could not tell from the best
    // (score within ambiguity_ratio of it): in look-alike places (the simulated office's rooms)
    // the right one is often not among the first three of several equal scores.
    size_t n = std::min(found.hypotheses.size(), static_cast<size_t>(rp.verify_hypotheses));
    while (n < found.hypotheses.size() && found.hypotheses[n].ratio_to_best >= rp.ambiguity_ratio) ++n;
    std::vector<SE3d> tries;
    for (size_t i = 0; i < n; ++i) tries.push_back(found.hypotheses[i].T_map_lidar);
    rr.search_ms = msSince(t0);

    // Verify: the fine registration from each hypothesis, coarse to fine in the voxel map
    // whatever the tracking association (doc/map.md: its metre-sized levels forgive the search's
    // 0.25 m / 1.5 deg steps, and it is fast), with no prior and no jump check.
    t0 = Clock::now();
    std::vector<Attempt> attempts = verifier_.verify(f, tries, rep, VerifyAs::Hypothesis, judge);
    for (size_t i = 0; i < attempts.size(); ++i) {
        const Attempt& a = attempts[i];
        const Vec3d& x = a.rep.T_map_lidar.translation();
        log_.logFmt(mrpt::system::LVL_DEBUG,
                    "hypothesis %zu (score %.3f): -> (%.2f %.2f %.2f), moved %.2f m, inliers %.3f, %s%s %s", i,
                    found.hypotheses[i].score, x.x(), x.y(), x.z(), translationDistance(a.rep.T_map_lidar, tries[i]),
                    a.rep.inlier_ratio, healthName(a.verdict.health), verifier_.fits(a) ? " verified" : "",
                    a.verdict.reason.c_str());
    }
    rr.verify_ms = msSince(t0);
    std::vector<Attempt> verified, standing;
    sortOut(std::move(attempts), verified, standing);
    rr.verified = static_cast<int>(verified.size());
    if (!rank(verified, rr, d)) return d;
    const Attempt& best = verified.front();
    // Ambiguous: another pose that stands (verified, or only unsettled), in another place,
    // explains the scan about as well; or, while candidates are tracked (refined on this scan
    // already), one of them does (a scan's pose is taken only when it beats them as it beats its
    // own hypotheses); or the winner has an axis the scan does not constrain (gamma below the
    // health check's weak_gamma on x, y or z: a corridor's scan fits anywhere along it).
    std::string ambiguous;
    for (const Attempt& o : standing)
        if (rival(best.rep, o.rep, false)) {
            rr.alternatives.push_back(o.rep.T_map_lidar);
            ambiguous = "alternatives";
        }
    for (const FrameReport* c : candidates_.reports())
        if (rival(best.rep, *c, false)) {
            rr.alternatives.push_back(c->T_map_lidar);
            if (ambiguous.find("candidates") == std::string::npos)
                ambiguous += std::string(ambiguous.empty() ? "" : "+") + "candidates";
        }
    for (int k = 0; k < 3; ++k)
        if (best.rep.gamma[k] < params_.health.weak_gamma)
            ambiguous += (ambiguous.empty() ? "" : "+") + mrpt::format("weak_%s:%.2f", kAxisNames[k], best.rep.gamma[k]);
    if (!ambiguous.empty()) {
        // Not committed: the frame stays as it was (lost), reporting the best pose found and its
        // alternatives. A frame without a pose (lost, or relocalize()) keeps every attempt that
        // stands as a candidate, tracked over the next scans; else, or with track_candidates =
        // 0, the next scan searches again.
        rr.outcome = RelocOutcome::Ambiguous;
        rr.detail = ambiguous;
        rr.alternatives.insert(rr.alternatives.begin(), best.rep.T_map_lidar);
        if (rp.track_candidates > 0 && (own_lost || pending_)) {
            // The frame reports the best-fitting pose (lost all the same).
            d.shown = RecoveryDecision::Shown{best.rep.T_map_lidar, best.rep.T_map_imu};
            rr.candidates = candidates_.admit(std::move(standing), rr.trigger);
        }
        report(rr, d);
        return d;
    }
    if (!own_lost && !pending_ && f.pred.used_imu && imu_chain_ &&
        (translationDistance(best.rep.T_map_lidar, rep.T_map_lidar) > rp.doubt_max_xyz ||
         rotationAngle(best.rep.T_map_lidar, rep.T_map_lidar) > rp.doubt_max_deg * kDeg)) {
        // A frame only in doubt, predicted by the IMU, is corrected, not moved to another place:
        // a pose that far from its own solve is another floor or another corridor (multifloor:
        // 3 m up a stairwell). Without IMU the prediction itself may be metres off (campus), and
        // so may an IMU chain that started from such a frame (imu_chain_).
        rr.outcome = RelocOutcome::TooFar;
        report(rr, d);
        return d;
    }
    if (!own_lost && best.rep.inlier_ratio <= rep.inlier_ratio) {
        // The frame's own solve stands (a suspicious frame the search could not better).
        rr.outcome = RelocOutcome::NotBetter;
        report(rr, d);
        return d;
    }
    accept(f, own, best, rr, d);
    report(rr, d);
    return d;
}

}  // namespace superloc::localization
