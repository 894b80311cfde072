// The commit rule of the candidate tracking (candidates.h, doc/relocalization.md §4): the best
// candidate is taken only when it fits healthily, has evidence from enough frames, every other
// candidate is ruled out over the frames both were tracked, and every translation of it is held.
#include <mrpt/core/format.h>
#include <superloc/core/se3.h>
#include <superloc/localization/candidates.h>

#include <algorithm>

namespace superloc::localization {
namespace {
using mrpt::system::LVL_DEBUG;
}  // namespace

bool CandidateTracker::weakAxesHeld(Frame& f, const Candidate& c, const HealthJudge& judge) {
    // A translation the scan constrains weakly (gamma below weak_gamma: the risk, before the
    // solve) may still be held at the scale of the candidates: probe it. The candidate is moved
    // track_probe_xyz along each weak axis, both ways, and verified again; the axis is held when
    // every probe comes back (within max_pred_xyz) or fits clearly worse (under track_ratio x
    // the candidate's inlier ratio). Along a featureless corridor a probe stays where it was put
    // and fits as well: not held.
    const auto& rp = params_.relocalization;
    const SE3d T_c = c.state.T_map_imu();
    for (int k = 0; k < 3; ++k) {
        if (!c.checks.weak[k]) continue;
        for (const double sign : {-1.0, 1.0}) {
            fusion::FrameState start = c.state;
            start.setPose(SE3d(Eigen::Translation3d(T_c.linear().col(k) * sign * rp.track_probe_xyz)) * T_c);
            const Attempt a = verifier_.verify(f, start, c.rep, VerifyAs::Hypothesis, judge);
            const FrameReport& r = a.rep;
            const double back = translationDistance(r.T_map_lidar, c.rep.T_map_lidar);
            const bool worse = r.diverged || r.inlier_ratio < rp.track_ratio * c.rep.inlier_ratio;
            log_.logFmt(LVL_DEBUG, "  probe %s%c %.1f m: back to %.2f m, inliers %.3f vs %.3f", sign < 0 ? "-" : "+",
                        "xyz"[k], rp.track_probe_xyz, back, r.inlier_ratio, c.rep.inlier_ratio);
            if (!(back <= params_.health.max_pred_xyz || worse)) return false;
        }
    }
    return true;
}

RecoveryDecision CandidateTracker::decide(Frame& f, const FrameReport& rep, const RelocReport& searched,
                                          const HealthJudge& judge) {
    const auto& rp = params_.relocalization;
    const double ref = judge.reference();
    RecoveryDecision d;
    RelocReport rr;
    rr.mode = "track";
    rr.trigger = trigger_;
    rr.outcome = RelocOutcome::Failed;
    rr.hypotheses = searched.hypotheses;
    rr.search_ms = searched.search_ms;
    rr.verify_ms = searched.verify_ms + track_ms_;
    const std::string budget = (over_budget_ ? mrpt::format("+over_budget:%d", over_budget_) : "") +
                               (searched.mode.empty() ? "" : "+search:" + std::string(relocOutcomeName(searched.outcome)));
    rr.verified = rr.candidates = static_cast<int>(set_.size());
    if (set_.empty()) {
        rr.detail = mrpt::format("candidates_dropped:%d", dropped_) + budget;
        d.outcome = rr.outcome;
        d.reloc = rr;
        return d;
    }
    // The best: the highest mean inlier ratio over its frames.
    const auto mean = [](const Candidate& c) { return c.evidence / c.frames; };
    std::stable_sort(set_.begin(), set_.end(), [&](const Candidate& a, const Candidate& b) { return mean(a) > mean(b); });
    const Candidate& best = set_.front();
    for (const Candidate& c : set_) rr.alternatives.push_back(c.rep.T_map_lidar);
    // Commit (doc/relocalization.md §4): the best fits healthily on this frame (settled, no
    // inlier flag, every translation constrained, its motion agreeing with the IMU's, and with
    // no reference yet accept_inlier_ratio), has evidence from track_min_frames frames, and
    // every other candidate is ruled out over the frames both were tracked: its summed inlier
    // ratio at most track_ratio x the best's (the single scan's margin, on summed evidence), or
    // the best ahead of it on each of the last track_consistent_frames of them.
    // A translation the scan leaves weak on this frame counts as constrained when it was
    // constrained on an earlier frame of the candidate and carried since by measured motion, or
    // when probing it (weakAxesHeld, only once everything else says commit) finds it held (the
    // simulated cave: gamma_x 0.00-0.23 on nearly every scan of the tunnel, yet the pose 2 m
    // along it fits clearly worse).
    const HealthChecks& bc = best.checks;
    const bool carried = best.axis_held[0] && best.axis_held[1] && best.axis_held[2];
    const bool fit_ok = !bc.not_converged && !bc.badFit() && !bc.prediction &&
                        (ref > 0 || best.rep.inlier_ratio >= rp.accept_inlier_ratio);
    bool margin = true;
    double worst_ratio = 0;
    std::vector<bool> ruled(set_.size(), false);
    for (size_t i = 1; i < set_.size(); ++i) {
        const Candidate& a = set_[i];
        const size_t common = std::min(a.history.size(), best.history.size());
        double sa = 0, sb = 0;
        size_t ahead = 0;
        for (size_t j = 0; j < common; ++j) {
            const double ha = a.history[a.history.size() - 1 - j], hb = best.history[best.history.size() - 1 - j];
            sa += ha;
            sb += hb;
            // consecutive frames ahead (by more than a tie: under track_lead x), from the latest
            if (ha < rp.track_lead * hb && ahead == j) ++ahead;
        }
        const double ratio = sb > 0 ? sa / sb : 1.0;
        worst_ratio = std::max(worst_ratio, ratio);
        const bool ruled_out = ratio <= rp.track_ratio || static_cast<int>(ahead) >= rp.track_consistent_frames;
        log_.logFmt(LVL_DEBUG,
                    "  vs candidate at (%.2f %.2f), %zu frames, last %.3f vs %.3f: ratio %.3f, best ahead on %zu "
                    "of %zu%s",
                    a.rep.T_map_lidar.translation().x(), a.rep.T_map_lidar.translation().y(), a.history.size(),
                    a.history.back(), best.history.back(), ratio, ahead, common, ruled_out ? ": ruled out" : "");
        margin = margin && ruled_out;
        ruled[i] = ruled_out;
    }
    rr.evidence_ratio = worst_ratio;
    log_.logFmt(LVL_DEBUG, "best candidate at (%.2f %.2f), %zu frames, mean %.3f",
                best.rep.T_map_lidar.translation().x(), best.rep.T_map_lidar.translation().y(), best.history.size(),
                mean(best));
    // A hypothesis of this frame's search that found no place in the full set was not judged.
    margin = margin && !left_out_;
    // ...and something was told apart: another candidate ruled out here, or one dropped on the
    // way, or on track_consistent_frames frames a search proposed another place that fit
    // clearly worse than the set (so never joined it). A lone candidate never compared with
    // anything is no evidence (simulated cave: a lone pose 89 m off, inlier ratio 0.40, survived
    // two frames); one every search keeps finding, with the other places it finds clearly worse
    // frame after frame, is (simulated cave: a lone right candidate, inlier ratio 1.00 on 16
    // frames, its searches' other places 0.44-0.59, was never committed).
    const bool compared =
        set_.size() > 1 || judged_ > 0 || outranked_frames_ >= rp.track_consistent_frames;
    const bool ready = fit_ok && margin && compared && best.frames >= rp.track_min_frames;
    const bool held = carried || (ready && weakAxesHeld(f, best, judge));
    if (!(ready && held)) {
        // Candidates ruled out stay tracked (the next searches find their places again: a
        // judged place must not come back as a new, unjudged candidate), but yield their places
        // in the set to new ones when it is full.
        for (size_t i = 0; i < set_.size(); ++i) set_[i].ruled_out = ruled[i];
        rr.outcome = RelocOutcome::Ambiguous;
        rr.detail = mrpt::format("candidates:%zu", set_.size()) + (fit_ok ? "" : "+unhealthy") + (held ? "" : "+weak") +
                    (compared ? "" : "+alone") + (margin ? "" : mrpt::format("+margin:%.3f", rr.evidence_ratio)) +
                    (left_out_ ? "+full" : "") + budget;
        // Lost all the same, reporting the best candidate's pose.
        d.shown = RecoveryDecision::Shown{best.rep.T_map_lidar, best.rep.T_map_imu};
        if (age_ >= rp.track_max_frames) {
            // Not settled in that many frames: the right pose may not be in the set at all.
            set_.clear();
            rr.detail += "+expired";
            rr.candidates = 0;
        }
        d.outcome = rr.outcome;
        d.reloc = rr;
        return d;
    }
    FrameSolution sol;
    sol.state = best.state;
    sol.corr = best.corr;
    sol.stats = best.stats;
    sol.report = best.rep.track();
    rr.outcome = RelocOutcome::Accepted;
    rr.detail = mrpt::format("frames:%d", best.frames) + budget;
    log_.logFmt(mrpt::system::LVL_INFO,
                "frame %zu (t=%.3f): relocalized by tracking %zu candidates over %d frames (evidence ratio %.3f, "
                "%.0f ms), inlier ratio %.2f",
                rep.index, rep.t, set_.size(), best.frames, rr.evidence_ratio, rr.verify_ms, best.rep.inlier_ratio);
    d.taken = std::move(sol);
    d.recovered = true;
    d.outcome = rr.outcome;
    d.reloc = rr;
    set_.clear();
    return d;
}

}  // namespace superloc::localization
