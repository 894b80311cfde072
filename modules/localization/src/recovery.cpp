// The Recovery (recovery.h): when a frame searches, what it takes, and what is carried to the
// next frames (the doubt, the last frame not lost). The policies themselves are in
// start_check.cpp, lost_search.cpp and candidates.cpp.
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/localization/recovery.h>

#include <algorithm>
#include <cmath>

namespace superloc::localization {

Recovery::Recovery(const LocalizerParams& params, SolveFn solve, const SensorHistory& sensors,
                   const mrpt::system::COutputLogger& log)
    : params_(params),
      sensors_(sensors),
      log_(log),
      verifier_(std::move(solve), params_.relocalization),
      candidates_(params, verifier_, sensors, log) {}

void Recovery::relocalize(const std::optional<reloc::SearchRegion>& region) {
    if (!search_) throw ConfigError("relocalize(): [relocalization] enabled = false");
    pending_ = true;
    region_ = region;
}

RecoveryDecision Recovery::withoutPose(Frame& f, const OwnPose& own, const HealthJudge& judge) {
    // relocalize() (e.g. --initial-pose auto): this scan is localized by the search alone.
    // Until a pose is accepted, every scan searches again, or, after an ambiguous search,
    // tracks its candidates (doc/relocalization.md §4); a lost frame's candidates likewise.
    // The frame's own report says no_pose (lost).
    const auto& rp = params_.relocalization;
    RecoveryDecision d;
    if (!candidates_.empty()) d.ms += candidates_.refine(f, own.rep, judge);
    const bool tracking = !candidates_.empty();
    RelocReport searched;
    if (!tracking || (rp.track_search_every > 0 && candidates_.age() % rp.track_search_every == 0)) {
        // A fresh search, where relocalize() asked or a lost frame looks; while candidates are
        // tracked, its hypotheses join them (and its winner must beat them too).
        std::optional<reloc::SearchRegion> region = region_;
        if (!pending_) region = lostRegion(f.scan->t, lost_run_ + 1);
        RecoveryDecision s = search(f, region ? &*region : nullptr, own, judge);
        s.ms += d.ms;
        d = std::move(s);
        if (d.reloc) searched = *d.reloc;
    }
    if (tracking && d.outcome != RelocOutcome::Accepted) {
        // The candidates decide; the search's time stays, and so does the pose it showed unless
        // the candidates show or take one.
        RecoveryDecision c = candidates_.decide(f, own.rep, searched, judge);
        c.ms += d.ms;
        if (!c.taken && !c.shown) c.shown = d.shown;
        // The next frame starts coarse, as after any relocalization of a lost frame.
        c.restart = c.taken.has_value();
        d = std::move(c);
    }
    if (d.outcome == RelocOutcome::Accepted) pending_ = false, doubt_ = false, candidates_.clear();
    return d;
}

RecoveryDecision Recovery::recoverIfLost(Frame& f, bool may_search, const OwnPose& own, const HealthJudge& judge) {
    // Lost for local_after_lost frames searches around the last pose not lost, for
    // global_after_lost frames the whole map.
    const auto& rp = params_.relocalization;
    std::vector<HealthEvidence> evidence;
    lost_run_ = own.verdict.health == Health::Lost ? lost_run_ + 1 : 0;
    // A frame that stands but whose registration is in doubt (degraded: it fits clearly worse
    // than this map gives when tracking is right, or did not settle in its rounds) gets the
    // local search too. The search's pose replaces the frame's only when verified with more
    // inliers.
    // After such a frame the search could not settle, the frames that follow are not `ok` before
    // a search confirms them: tracking from a doubtful pose can settle in a wrong basin and fit
    // as well as a right one (kitti00-mini split: 1.1 m along the road, converged).
    const HealthChecks& c = own.verdict.checks;  // as solved
    const bool unconfirmed = search_ && doubt_ && own.verdict.health == Health::Ok;
    Verdict v = own.verdict;
    if (unconfirmed) {
        v = judge.amend(v, HealthEvidence::Unconfirmed);
        evidence.push_back(HealthEvidence::Unconfirmed);
    }
    // A frame that fits clearly worse is searched whatever its risk says (its gamma was measured
    // at a pose that may be wrong); one only unsettled is not where the scan leaves a translation
    // unconstrained (a corridor: the search could not tell the places along it apart).
    const bool suspicious =
        v.health == Health::Degraded && (c.badFit() || ((c.inDoubt() || unconfirmed) && !c.weakTranslation()));
    // A frame only in doubt (not lost, not fitting clearly worse) less than doubt_search_period
    // after a doubt's search found nothing better (the frame's pose confirmed: the map disagrees
    // with the scans there, and a search every frame would only confirm it again) waits: it keeps
    // its pose, degraded, and its doubt goes on to the next frame. A search that moved the pose
    // does not hold the next one back: tracking from there is what is in question.
    const bool lost_search = lost_run_ >= rp.local_after_lost;
    const bool wants = search_ && may_search && (lost_search || suspicious);
    const bool deferred = wants && !lost_search && !c.badFit() && confirmed_t_ &&
                          f.scan->t - *confirmed_t_ < rp.doubt_search_period;
    if (!wants || deferred) {
        if (c.inDoubt() || v.health == Health::Lost || deferred) doubt_ = true;
        RecoveryDecision d;
        d.evidence = std::move(evidence);
        if (deferred) {
            d.reloc.emplace();
            d.reloc->trigger = "doubt";
            d.reloc->outcome = RelocOutcome::Deferred;
        }
        return d;
    }
    const auto region = lostRegion(f.scan->t, lost_run_);
    RecoveryDecision s = search(f, region ? &*region : nullptr, OwnPose{own.sol, own.rep, v}, judge);
    switch (s.outcome) {
        case RelocOutcome::Accepted:
            // The pose taken is judged afresh: the evidence so far was about the frame's own and
            // does not go with it. It was verified, so not lost.
            lost_run_ = 0;
            confirmed_t_.reset();
            doubt_ = false;
            return s;
        case RelocOutcome::NotBetter:
            // Nothing around fits better: the frame's own pose is confirmed.
            doubt_ = false;
            if (!lost_search) confirmed_t_ = f.scan->t;
            if (unconfirmed) evidence.push_back(HealthEvidence::Confirmed);
            break;
        default:
            if (c.inDoubt()) doubt_ = true;
            break;
    }
    s.evidence = std::move(evidence);
    return s;
}

Recovery::NextFrame Recovery::endFrame(const Frame& f, const fusion::FrameState& state, const FrameReport& rep,
                                       bool restart) {
    prev_verified_ = rep.health == Health::Ok || rep.recovered;
    if (rep.health == Health::Ok)
        imu_chain_ = true;
    else if (!f.pred.used_imu)
        imu_chain_ = false;
    fusion::FrameState next = state;
    if (rep.health != Health::Lost) {
        last_good_ = GoodFrame{state, rep.T_map_lidar};
        last_good_->state.t = f.scan->t;
    } else if (last_good_ && search_) {
        // A lost frame's state is not carried: its pose, and the velocity an IMU factor made
        // of it, would drive every later prediction (multifloor ndt ran away to kilometres).
        // Tracking resumes from the last frame not lost, at rest, velocity unknown.
        next = last_good_->state;
        next.t = f.scan->t;
        next.setVelocity(Vec3d::Zero());
        restart = true;
    }
    return NextFrame{next, restart};
}

void Recovery::accept(const Frame& f, const Attempt& own, const Attempt& best, RelocReport& rr, RecoveryDecision& d) {
    FrameSolution sol = best.sol;
    const bool lost_before = own.rep.diverged || own.verdict.health == Health::Lost;
    if (!lost_before) {
        // A frame in doubt was tracked: its velocity (IMU-integrated, or constant velocity) is
        // the platform's, in a frame rotated by the correction. The verification solved from
        // rest, so carry it over (a dropout over an IMU gap: 0.63 m off on the next frame
        // without).
        const Mat3d R_corr = best.rep.T_map_lidar.linear() * own.rep.T_map_lidar.linear().transpose();
        sol.state.setVelocity(R_corr * own.sol.state.velocity());
    }
    d.taken = std::move(sol);
    d.recovered = true;
    rr.outcome = RelocOutcome::Accepted;
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
    const bool corrected_far = translationDistance(best.rep.T_map_lidar, own.rep.T_map_lidar) > hp.max_pred_xyz ||
                               rotationAngle(best.rep.T_map_lidar, own.rep.T_map_lidar) > hp.max_pred_deg * kDeg;
    d.restart = d.restart || lost_before || (corrected_far && (f.pred.used_imu || !prev_verified_));
    log_.logFmt(mrpt::system::LVL_INFO,
                "frame %zu (t=%.3f): relocalized (%s search %.0f ms, %d of %d hypotheses verified in %.0f ms), "
                "inlier ratio %.2f",
                own.rep.index, own.rep.t, rr.mode.c_str(), rr.search_ms, rr.verified, rr.hypotheses, rr.verify_ms,
                best.rep.inlier_ratio);
}

void Recovery::sortOut(std::vector<Attempt>&& attempts, std::vector<Attempt>& verified,
                       std::vector<Attempt>& standing) const {
    // Every attempt that is not lost, settled or not, stands: an alternative that fits about as
    // well but did not settle in its rounds is no evidence against it (look-alike rooms).
    for (Attempt& a : attempts) {
        if (verifier_.fits(a)) verified.push_back(a);
        if (a.verdict.health != Health::Lost) standing.push_back(std::move(a));
    }
}

bool Recovery::rank(std::vector<Attempt>& verified, RelocReport& rr, RecoveryDecision& d) const {
    if (verified.empty()) {
        rr.detail = "verification";
        report(rr, d);
        return false;
    }
    std::sort(verified.begin(), verified.end(),
              [](const Attempt& a, const Attempt& b) { return a.rep.inlier_ratio > b.rep.inlier_ratio; });
    return true;
}

void Recovery::report(const RelocReport& rr, RecoveryDecision& d) {
    d.outcome = rr.outcome;
    d.reloc = rr;
    d.ms += rr.search_ms + rr.verify_ms;
}

bool Recovery::rival(const FrameReport& best, const FrameReport& o, bool start) const {
    const auto& rp = params_.relocalization;
    const bool distinct = start ? !rp.sameStartBasin(o.T_map_lidar, best.T_map_lidar)
                                : !rp.samePlace(o.T_map_lidar, best.T_map_lidar);
    return distinct && o.inlier_ratio >= rp.ambiguity_ratio * best.inlier_ratio;
}

std::optional<reloc::SearchRegion> Recovery::lostRegion(double t, int lost_run) const {
    const auto& rp = params_.relocalization;
    if (lost_run >= rp.global_after_lost || !last_good_) return std::nullopt;
    reloc::SearchRegion region;
    region.centre = last_good_->T_map_lidar.translation();
    region.radius = rp.local_radius + rp.local_radius_rate * std::max(0.0, t - last_good_->state.t);
    const Mat3d& R = last_good_->T_map_lidar.linear();
    region.yaw = std::atan2(R(1, 0), R(0, 0));
    region.yaw_half_width = rp.local_yaw_deg * kDeg;
    return region;
}

}  // namespace superloc::localization
