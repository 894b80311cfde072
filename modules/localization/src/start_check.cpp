// The start-check policy of the Recovery (recovery.h, doc/health.md "Start"): the first frame
// from a given initial pose is solved again from seeds within that pose's uncertainty
// (StartPose::seeds); the frame's own solve is one of the rivals. The best fit is taken; a start
// that fits about as well elsewhere keeps its own solve, reported degraded (start_ambiguous).
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/localization/recovery.h>
#include <superloc/localization/start_pose.h>

#include <algorithm>
#include <utility>

namespace superloc::localization {
namespace {
using Clock = SteadyClock;
}  // namespace

std::vector<SE3d> Recovery::startBasins(Frame& f, const std::vector<SE3d>& seeds, const FrameReport& rep) {
    // Each seed solved in the voxel map (fast, as a search hypothesis); one pose per basin the
    // seeds reach, best first, kept where it fits at least start_refine_ratio x the best basin
    // (measured: refining every basin cost 919 ms on the KITTI split, these 219 ms).
    const auto& rp = params_.relocalization;
    std::vector<std::pair<SE3d, double>> basins;  // pose, inlier ratio
    for (const SE3d& T_seed : seeds) {
        const Attempt a = verifier_.verify(f, std::vector<SE3d>{T_seed}, rep, VerifyAs::Hypothesis).front();
        if (a.rep.diverged) continue;
        const SE3d& T = a.rep.T_map_lidar;
        if (std::none_of(basins.begin(), basins.end(), [&](const auto& b) { return rp.sameStartBasin(b.first, T); }))
            basins.emplace_back(T, a.rep.inlier_ratio);
    }
    std::sort(basins.begin(), basins.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    std::vector<SE3d> tries;
    for (const auto& [T, ratio] : basins)
        if (ratio >= rp.start_refine_ratio * basins.front().second) tries.push_back(T);
    return tries;
}

void Recovery::checkStart(Frame& f, const SE3d& T0, FrameSolution& sol, FrameReport& rep) {
    const auto& rp = params_.relocalization;
    const std::vector<SE3d> seeds = StartPose::seeds(T0, rp);
    if (seeds.empty()) return;
    RelocReport rr;
    rr.mode = "start";
    rr.trigger = "start";
    rr.outcome = RelocOutcome::Failed;
    const Attempt own{rep, sol, rep.health, rep.checks, ""};
    // Proposals: the basins the seeds reach, each verified by the frame's own registration so
    // that it compares with the frame's own solve.
    auto t0 = Clock::now();
    rr.hypotheses = static_cast<int>(seeds.size());
    const std::vector<SE3d> tries = startBasins(f, seeds, rep);
    rr.search_ms = msSince(t0);
    t0 = Clock::now();
    std::vector<Attempt> verified, standing;
    sortOut(verifier_.verify(f, tries, rep, VerifyAs::FirstFrame), verified, standing);
    rr.verify_ms = msSince(t0);
    rr.verified = static_cast<int>(verified.size());
    if (rep.health != Health::Lost && !rep.diverged) {
        // The start's own solve (from the given pose) is one of the results compared.
        if (verifier_.fits(own)) verified.push_back(own);
        standing.push_back(own);
    }
    const StageTimes ms = rep.ms;
    if (!rank(verified, ms, rr, rep)) return;
    const Attempt& best = verified.front();
    // Ambiguous: a result in another basin of the start (start_distinct_*) explains the scan
    // about as well. (A translation the scan leaves open is told by this rule already: the seeds
    // along it settle where they started, fitting alike.)
    for (const Attempt& o : standing)
        if (rival(best.rep, o.rep, true)) rr.alternatives.push_back(o.rep.T_map_lidar);
    if (!rr.alternatives.empty()) {
        rr.outcome = RelocOutcome::Ambiguous;
        rr.detail = "alternatives";
        rr.alternatives.insert(rr.alternatives.begin(), best.rep.T_map_lidar);
        if (!rep.diverged && rep.health != Health::Lost && rep.inlier_ratio < rp.ambiguity_ratio * best.rep.inlier_ratio) {
            // A start whose own solve fits clearly worse than rivals that tie among themselves
            // (kitti00-mini from 1.0 m / 1.0 m / 10 deg off: own 0.37, two seeds 0.62 and 0.62,
            // 0.6 m apart): the best-fitting of them is taken, reported ambiguous all the same,
            // and the next frame starts with its velocity unknown.
            sol = best.sol;
            rep = best.rep;
            restart_ = true;
        }
        report(ms, rr, rep);
        // Another result within the start's uncertainty fits about as well: the pose is kept,
        // but not as `ok`. (The frames after it are not held in doubt: on kitti00-mini their
        // searches took poses 0.4 m along the road, as the start's rivals were.)
        health_.amend(rep, HealthEvidence::StartAmbiguous);
        return;
    }
    if (rep.health != Health::Lost &&
        (best.rep.inlier_ratio <= rep.inlier_ratio || rp.sameStartBasin(best.rep.T_map_lidar, rep.T_map_lidar))) {
        // The frame's own solve stands (the best seed ends where the own solve did, or fits no better).
        rr.outcome = RelocOutcome::NotBetter;
        report(ms, rr, rep);
        return;
    }
    accept(f, own, best, rr, sol, rep);
    report(ms, rr, rep);
    rep.recovered = true;
    assess(rep);
}

}  // namespace superloc::localization
