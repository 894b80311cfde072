// Relocalization (doc/health.md, step 7): the global search proposes poses for the current scan,
// the localizer's own fine registration verifies each, and the health checks and the alignment
// risk decide whether one of them can be committed.
#include <mrpt/core/format.h>
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/localization/localizer.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace superloc::localization {
namespace {
using Clock = SteadyClock;
}  // namespace

void Localizer::restore(const Solution& s) {
    cur_ = s.state;
    corr_ = s.corr;
    last_stats_ = s.stats;
    last_T_map_lidar_ = s.T_map_lidar;
}

FrameReport Localizer::refineHypothesis(const Scan& scan, const fusion::FrameState& start, const FrameReport& base,
                                        Solve kind, const Prediction* frame_pred) {
    FrameReport r = base;
    r.diverged = false;
    r.diverged_reason.clear();
    r.converged = false;
    r.rounds = r.iterations = 0;
    cur_ = start;
    cur_.t = scan.t;
    const auto marginal = cur_marginal_;
    solveIcp(nullptr, true, r, kind);
    cur_marginal_ = marginal;
    if (frame_pred && wantsSweepVelocity(*frame_pred) && !r.diverged)
        solveSweepVelocity(scan, *frame_pred, nullptr, r);
    if (!assoc_.voxel && kind == Solve::Hypothesis) {
        // Inliers measured as tracking measures them, so that the refined poses compare with
        // the frame's own solve (the two associations count inliers differently).
        const auto ta = Clock::now();
        associate(features_.pts_body, cur_.T_map_imu(), *map_, assoc_, corr_, last_stats_);
        r.ms.associate += msSince(ta);
    }
    // No IMU prediction (a start's seed: the frame's own, from another pose): finished unchecked.
    Prediction p = frame_pred ? *frame_pred : Prediction{};
    p.T_map_imu = start.T_map_imu();
    finish(scan, p, true, r);
    r.pred_dxyz = translationDistance(r.T_map_lidar, r.T_map_lidar_pred);
    r.pred_ddeg = rotationAngle(r.T_map_lidar, r.T_map_lidar_pred) / kDeg;
    return r;
}

RelocOutcome Localizer::runRelocalization(const Scan& scan, const Prediction& pred, const reloc::SearchRegion* region,
                                  FrameReport& rep, const std::vector<SE3d>* seeds) {
    const auto& rp = params_.relocalization;
    RelocReport rr;
    rr.mode = seeds ? "start" : region ? "local" : "global";
    rr.trigger = seeds                           ? "start"
                 : reloc_pending_                ? "request"
                 : rep.health == Health::Lost    ? "lost"
                                                 : "doubt";
    rr.outcome = RelocOutcome::Failed;

    // The frame's own solve, as it stands before any attempt moves the state.
    struct Outcome {
        FrameReport rep;
        Solution sol;
    };
    const Outcome own{rep, solution()};

    // Proposals: the basins a start's seeds reach (startBasins, localizer_start.cpp: each seed
    // solved in the voxel map), or the global search's hypotheses.
    std::vector<SE3d> tries;
    std::vector<double> scores;  // the search's score of each (for the log)
    auto t0 = Clock::now();
    if (seeds) {
        rr.hypotheses = static_cast<int>(seeds->size());
        tries = startBasins(scan, *seeds, rep);
    } else {
        // Gravity: the IMU-predicted attitude when there is one, else the search estimates it
        // from the scan's ground plane.
        std::optional<Mat3d> R_level;
        if (pred.used_imu)
            R_level = Mat3d((pred.T_map_imu * scan.T_imu_lidar).linear());
        else if (const auto R_level_imu = params_.loc.use_imu ? sensors_.gravityAt(scan.t, params_.imu.gravity) : std::nullopt)
            R_level = Mat3d(*R_level_imu * scan.T_imu_lidar.linear());
        const reloc::GlobalSearchResult found = search_->search(scan.points, R_level, region);
        rr.hypotheses = static_cast<int>(found.hypotheses.size());
        if (found.hypotheses.empty()) {
            rr.search_ms = msSince(t0);
            rr.detail = "no_hypothesis" + (found.failure.empty() ? "" : ": " + found.failure);
            rep.reloc = rr;
            rep.ms.solve += rr.search_ms;
            return rr.outcome;
        }
        // The best verify_hypotheses, and every other one the search could not tell from the
        // best (score within ambiguity_ratio of it): in look-alike places (the simulated
        // office's rooms) the right one is often not among the first three of several equal
        // scores.
        size_t n = std::min(found.hypotheses.size(), static_cast<size_t>(rp.verify_hypotheses));
        while (n < found.hypotheses.size() && found.hypotheses[n].ratio_to_best >= rp.ambiguity_ratio) ++n;
        for (size_t i = 0; i < n; ++i) {
            tries.push_back(found.hypotheses[i].T_map_lidar);
            scores.push_back(found.hypotheses[i].score);
        }
    }
    rr.search_ms = msSince(t0);

    // Verify: the fine registration from each hypothesis, as on a first frame (velocity unknown,
    // coarse start, no prior, no jump check), then the health checks.
    std::vector<Outcome> verified;
    // Every attempt that is not lost, settled or not: an alternative that fits about as well
    // but did not settle in its rounds is no evidence against it (look-alike rooms).
    std::vector<Outcome> standing;
    t0 = Clock::now();
    // A search's hypothesis is verified coarse to fine in the voxel map whatever the tracking
    // association (doc/map.md): its metre-sized levels forgive the search's 0.25 m / 1.5 deg
    // steps, and it is fast. A start's basin by the frame's own registration, so that it
    // compares with the frame's own solve.
    const double ref = health_.reference();
    // Around a start the places are nearer: a start result start_distinct_* from the winner is
    // another basin of the same registration.
    const auto distinct = [&](const SE3d& a, const SE3d& b) {
        return seeds ? !rp.sameStartBasin(a, b) : !rp.samePlace(a, b);
    };
    for (size_t i = 0; i < tries.size(); ++i) {
        fusion::FrameState start;
        start.setBias(prev_.bias());
        start.setPose(tries[i] * scan.T_imu_lidar.inverse());
        const FrameReport r = seeds ? refineHypothesis(scan, start, rep, Solve::Track, &pred)
                                    : refineHypothesis(scan, start, rep, Solve::Hypothesis);
        std::string why;
        HealthChecks c;
        const Health h = health_.classify(r, &why, &c);
        // Verified: settled, and fitting as tracking fits on this map (no inlier flag against the
        // run's reference; with none yet, accept_inlier_ratio). A pose that fits clearly worse
        // may stand as an alternative but is not taken (campus kidnap: a pose 9.4 m off, inlier
        // ratio under 0.9 x the reference, was taken when the right one was outside the region).
        const bool fits = !c.not_converged && h != Health::Lost && !c.badFit() &&
                          (ref > 0 || r.inlier_ratio >= rp.accept_inlier_ratio);
        if (fits) verified.push_back({r, solution()});
        if (h != Health::Lost) standing.push_back({r, solution()});
        const Vec3d& x = r.T_map_lidar.translation();
        MRPT_LOG_DEBUG_FMT("hypothesis %zu (score %.3f): -> (%.2f %.2f %.2f), moved %.2f m, inliers %.3f, %s%s %s", i,
                           i < scores.size() ? scores[i] : 0.0, x.x(), x.y(), x.z(),
                           translationDistance(r.T_map_lidar, tries[i]), r.inlier_ratio, healthName(h),
                           fits ? " verified" : "", why.c_str());
    }
    rr.verify_ms = msSince(t0);
    rr.verified = static_cast<int>(verified.size());
    if (seeds && rep.health != Health::Lost && !rep.diverged) {
        // The start's own solve (from the given pose) is one of the results compared.
        const HealthChecks& c = rep.checks;
        if (!c.not_converged && !c.badFit() && (ref > 0 || rep.inlier_ratio >= rp.accept_inlier_ratio))
            verified.push_back(own);
        standing.push_back(own);
    }
    const StageTimes ms = rep.ms;
    const auto report = [&](FrameReport& r) {
        r.ms = ms;
        r.ms.solve += rr.search_ms + rr.verify_ms;
        r.reloc = rr;
    };
    if (verified.empty()) {
        restore(own.sol);
        rr.detail = "verification";
        report(rep);
        return rr.outcome;
    }
    std::sort(verified.begin(), verified.end(),
              [](const Outcome& a, const Outcome& b) { return a.rep.inlier_ratio > b.rep.inlier_ratio; });
    const Outcome& best = verified.front();
    // Ambiguous: another pose that stands (verified, or only unsettled), distinct from the
    // winner, explains the scan about as well; or the winner has an axis the scan does not
    // constrain (gamma below the health check's weak_gamma on x, y or z: a corridor's scan fits
    // anywhere along it).
    std::string ambiguous;
    // A rival: a pose distinct from the winner's that explains the scan about as well.
    const auto rivals = [&](const FrameReport& o) {
        return distinct(o.T_map_lidar, best.rep.T_map_lidar) &&
               o.inlier_ratio >= rp.ambiguity_ratio * best.rep.inlier_ratio;
    };
    for (const Outcome& so : standing) {
        const FrameReport& o = so.rep;
        if (rivals(o)) {
            rr.alternatives.push_back(o.T_map_lidar);
            ambiguous = "alternatives";
        }
    }
    // While candidates are tracked (refined on this scan already), each is an alternative too:
    // one scan's pose is taken only when it beats them as it beats its own hypotheses.
    for (const Candidate& c : hypotheses_) {
        const FrameReport& o = c.rep;
        if (rivals(o)) {
            rr.alternatives.push_back(o.T_map_lidar);
            if (ambiguous.find("candidates") == std::string::npos)
                ambiguous += std::string(ambiguous.empty() ? "" : "+") + "candidates";
        }
    }
    // (Around a start, the rival rule already tells a translation the scan leaves open: the
    // seeds along it settle where they started, fitting alike.)
    for (int k = 0; k < 3 && !seeds; ++k)
        if (best.rep.gamma[k] < params_.health.weak_gamma)
            ambiguous += (ambiguous.empty() ? "" : "+") + mrpt::format("weak_%s:%.2f", kAxisNames[k], best.rep.gamma[k]);
    if (!ambiguous.empty()) {
        // Not committed: the frame stays as it was (lost), reporting the best pose found and
        // its alternatives. A frame without a pose (lost, or relocalize()) keeps every attempt
        // that stands as a candidate, tracked over the next scans (trackCandidates); else, or
        // with track_candidates = 0, the next scan searches again.
        rr.outcome = RelocOutcome::Ambiguous;
        rr.detail = ambiguous;
        rr.alternatives.insert(rr.alternatives.begin(), best.rep.T_map_lidar);
        if (seeds && !rep.diverged && rep.health != Health::Lost &&
            rep.inlier_ratio < rp.ambiguity_ratio * best.rep.inlier_ratio) {
            // A start whose own solve fits clearly worse than rivals that tie among themselves
            // (kitti00-mini from 1.0 m / 1.0 m / 10 deg off: own 0.37, two seeds 0.62 and 0.62,
            // 0.6 m apart): the best-fitting of them is taken, reported ambiguous all the same,
            // and the next frame starts with its velocity unknown.
            restore(best.sol);
            rep = best.rep;
            restart_ = true;
            report(rep);
            return rr.outcome;
        }
        restore(own.sol);
        // While candidates are tracked, the new ones (not already tracked) take the free places,
        // best fitting first: a tracked candidate is judged over its frames, not displaced by a
        // look-alike seen once (measured: the office's rooms replaced each other every frame).
        const bool tracking = !hypotheses_.empty();
        if (rp.track_candidates > 0 && (rep.health == Health::Lost || reloc_pending_)) {
            if (!tracking) candidates_age_ = 0, track_judged_ = 0;
            double best_tracked = 0;
            for (const Candidate& c : hypotheses_) best_tracked = std::max(best_tracked, c.rep.inlier_ratio);
            std::sort(standing.begin(), standing.end(),
                      [](const Outcome& a, const Outcome& b) { return a.rep.inlier_ratio > b.rep.inlier_ratio; });
            for (const Outcome& o : standing) {
                const bool same = std::any_of(hypotheses_.begin(), hypotheses_.end(), [&](const Candidate& c) {
                    return rp.samePlace(c.rep.T_map_lidar, o.rep.T_map_lidar);
                });
                if (same) continue;
                // While tracking: one that fits this scan clearly worse than the best tracked
                // candidate (under track_ratio x its inlier ratio) is no alternative.
                if (o.rep.inlier_ratio < rp.track_ratio * best_tracked) continue;
                if (static_cast<int>(hypotheses_.size()) >= rp.track_candidates) {
                    // Full: the worst candidate already ruled out yields its place, else this
                    // hypothesis is left out (and the frame commits nothing).
                    auto worst = hypotheses_.end();
                    for (auto it = hypotheses_.begin(); it != hypotheses_.end(); ++it)
                        if (it->ruled_out && (worst == hypotheses_.end() || it->evidence / it->frames <
                                                                                worst->evidence / worst->frames))
                            worst = it;
                    if (worst == hypotheses_.end()) {
                        track_left_out_ = true;
                        break;
                    }
                    hypotheses_.erase(worst);
                    ++track_judged_;
                }
                Candidate c;
                c.state = o.sol.state;
                c.evidence = o.rep.inlier_ratio;
                c.history.push_back(o.rep.inlier_ratio);
                c.frames = 1;
                c.rep = o.rep;
                health_.classify(o.rep, nullptr, &c.checks);
                for (int k = 0; k < 3; ++k) c.axis_held[k] = !c.checks.weak[k];
                c.corr = o.sol.corr;
                c.stats = o.sol.stats;
                hypotheses_.push_back(std::move(c));
            }
            if (!tracking) candidates_trigger_ = rr.trigger;
            rr.candidates = static_cast<int>(hypotheses_.size());
            // The frame reports the best-fitting pose (lost all the same).
            rep.T_map_lidar = best.rep.T_map_lidar;
            rep.T_map_imu = best.rep.T_map_imu;
        }
        report(rep);
        return rr.outcome;
    }
    if (rep.health != Health::Lost && !reloc_pending_ && pred.used_imu && imu_chain_ &&
        (translationDistance(best.rep.T_map_lidar, rep.T_map_lidar) > rp.doubt_max_xyz ||
         rotationAngle(best.rep.T_map_lidar, rep.T_map_lidar) > rp.doubt_max_deg * kDeg)) {
        // A frame only in doubt, predicted by the IMU, is corrected, not moved to another place:
        // a pose that far from its own solve is another floor or another corridor (multifloor:
        // 3 m up a stairwell). Without IMU the prediction itself may be metres off (campus), and
        // so may an IMU chain that started from such a frame (imu_chain_).
        restore(own.sol);
        rr.outcome = RelocOutcome::TooFar;
        report(rep);
        return rr.outcome;
    }
    if (rep.health != Health::Lost &&
        (best.rep.inlier_ratio <= rep.inlier_ratio || (seeds && !distinct(best.rep.T_map_lidar, rep.T_map_lidar)))) {
        // The frame's own solve stands (a suspicious frame the search could not better; a start
        // whose best seed ends where its own solve did).
        restore(own.sol);
        rr.outcome = RelocOutcome::NotBetter;
        report(rep);
        return rr.outcome;
    }
    restore(best.sol);
    if (!own.rep.diverged && own.rep.health != Health::Lost) {
        // A frame in doubt was tracked: its velocity (IMU-integrated, or constant velocity) is
        // the platform's, in a frame rotated by the correction. The verification solved from
        // rest, so carry it over (a dropout over an IMU gap: 0.63 m off on the next frame
        // without).
        const Mat3d R_corr = best.rep.T_map_lidar.linear() * own.rep.T_map_lidar.linear().transpose();
        cur_.setVelocity(R_corr * own.sol.state.velocity());
    }
    rep = best.rep;
    rr.outcome = RelocOutcome::Accepted;
    report(rep);
    rep.recovered = true;
    // After a loss (or with no pose at all) the velocity is unknown: the next frame starts
    // coarse. So it is after a correction larger than [health] max_pred_xyz / max_pred_deg:
    // the velocity was estimated along a track that far off (a dropout over an IMU gap: the
    // next frame was lost again, 0.97 m off). A frame corrected less keeps the velocity of the
    // frames before it.
    // Without IMU, when the frame before was itself verified (ok, or relocalized), the velocity
    // is known again from the two verified poses (the constant-velocity model takes it from
    // them): a zero-velocity restart there settled kitti00-mini's next odd frame 0.85 m back
    // along the road, reported ok (doc/results.md, health table).
    const auto& hp = params_.health;
    const bool lost_before = own.rep.diverged || own.rep.health == Health::Lost;
    const bool corrected_far = translationDistance(best.rep.T_map_lidar, own.rep.T_map_lidar) > hp.max_pred_xyz ||
                               rotationAngle(best.rep.T_map_lidar, own.rep.T_map_lidar) > hp.max_pred_deg * kDeg;
    restart_ = lost_before || (corrected_far && (pred.used_imu || !prev_verified_));
    MRPT_LOG_INFO_FMT("frame %zu (t=%.3f): relocalized (%s search %.0f ms, %d of %d hypotheses verified in %.0f ms), "
                      "inlier ratio %.2f",
                      rep.index, rep.t, rr.mode.c_str(), rr.search_ms, rr.verified, rr.hypotheses, rr.verify_ms,
                      rep.inlier_ratio);
    return rr.outcome;
}

void Localizer::assess(FrameReport& rep) {
    rep.pred_dxyz = translationDistance(rep.T_map_lidar, rep.T_map_lidar_pred);
    rep.pred_ddeg = rotationAngle(rep.T_map_lidar, rep.T_map_lidar_pred) / kDeg;
    health_.assess(rep);
}

void Localizer::recoverIfLost(const Scan& scan, const Prediction& pred, bool may_search, FrameReport& rep) {
    // Lost for local_after_lost frames searches around the last pose not lost, for
    // global_after_lost frames the whole map.
    const auto& rp = params_.relocalization;
    lost_run_ = rep.health == Health::Lost ? lost_run_ + 1 : 0;
    // A frame that stands but whose registration is in doubt (degraded: it fits clearly worse
    // than this map gives when tracking is right, or did not settle in its rounds) gets the
    // local search too. The search's pose replaces the frame's only when verified with more
    // inliers.
    // After such a frame the search could not settle, the frames that follow are not `ok` before
    // a search confirms them: tracking from a doubtful pose can settle in a wrong basin and fit
    // as well as a right one (kitti00-mini split: 1.1 m along the road, converged).
    const HealthChecks c = rep.checks;  // as solved (a search may replace rep)
    const bool unconfirmed = search_ && doubt_ && rep.health == Health::Ok;
    if (unconfirmed) {
        rep.health = Health::Degraded;
        rep.health_reason = "unconfirmed";
        rep.checks.unconfirmed = true;
    }
    // A frame that fits clearly worse is searched whatever its risk says (its gamma was measured
    // at a pose that may be wrong); one only unsettled is not where the scan leaves a translation
    // unconstrained (a corridor: the search could not tell the places along it apart).
    const bool suspicious =
        rep.health == Health::Degraded && (c.badFit() || ((c.inDoubt() || unconfirmed) && !c.weakTranslation()));
    if (!(search_ && may_search && (lost_run_ >= rp.local_after_lost || suspicious))) {
        if (c.inDoubt() || rep.health == Health::Lost) doubt_ = true;
        return;
    }
    const auto region = lostRegion(scan, lost_run_);
    switch (runRelocalization(scan, pred, region ? &*region : nullptr, rep)) {
        case RelocOutcome::Accepted:
            assess(rep);
            lost_run_ = rep.health == Health::Lost ? lost_run_ : 0;
            doubt_ = false;
            break;
        case RelocOutcome::NotBetter:
            // Nothing around fits better: the frame's own pose is confirmed.
            doubt_ = false;
            if (unconfirmed) {
                rep.health = Health::Ok;
                rep.health_reason.clear();
                rep.checks.unconfirmed = false;
            }
            break;
        default:
            if (c.inDoubt()) doubt_ = true;
            break;
    }
}

void Localizer::updateTrackingState(const Scan& scan, const Prediction& pred, const FrameReport& rep) {
    // The drift check's chain goes on through frames the IMU predicted from the one before,
    // solved by the frame's own registration.
    health_.recordFrame(rep, pred.used_imu && !rep.recovered && !restart_);
    prev_verified_ = rep.health == Health::Ok || rep.recovered;
    if (rep.health == Health::Ok)
        imu_chain_ = true;
    else if (!pred.used_imu)
        imu_chain_ = false;
    if (rep.health != Health::Lost) {
        last_good_ = GoodFrame{cur_, rep.T_map_lidar};
        last_good_->state.t = scan.t;
    } else if (last_good_ && search_) {
        // A lost frame's state is not carried: its pose, and the velocity an IMU factor made
        // of it, would drive every later prediction (multifloor ndt ran away to kilometres).
        // Tracking resumes from the last frame not lost, at rest, velocity unknown.
        cur_ = last_good_->state;
        cur_.t = scan.t;
        cur_.setVelocity(Vec3d::Zero());
        restart_ = true;
    }
}

}  // namespace superloc::localization
