// Multi-frame hypothesis tracking (doc/relocalization.md §4): one scan cannot tell look-alike
// places apart (the simulated office's rooms fit within 1-8 % of each other), several scans
// along the motion can. The candidates of an ambiguous relocalization are each carried by the
// measured motion, refined by the fine registration as hypotheses, and their evidence (summed
// inlier ratio) accumulated; one is committed only when it is clearly best over the frames.
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

std::optional<reloc::SearchRegion> Localizer::lostRegion(const Scan& scan, int lost_run) const {
    const auto& rp = params_.relocalization;
    if (lost_run >= rp.global_after_lost || !last_good_) return std::nullopt;
    reloc::SearchRegion region;
    region.centre = last_good_->T_map_lidar.translation();
    region.radius = rp.local_radius + rp.local_radius_rate * std::max(0.0, scan.t - last_good_->state.t);
    const Mat3d& R = last_good_->T_map_lidar.linear();
    region.yaw = std::atan2(R(1, 0), R(0, 0));
    region.yaw_half_width = rp.local_yaw_deg * kDeg;
    return region;
}

void Localizer::refineCandidates(const Scan& scan, FrameReport& rep) {
    const auto& rp = params_.relocalization;
    ++candidates_age_;
    track_dropped_ = track_over_budget_ = 0;
    track_left_out_ = false;
    // Best evidence first: under the time budget the weakest are the ones left out.
    std::sort(hypotheses_.begin(), hypotheses_.end(),
              [](const Candidate& a, const Candidate& b) { return a.evidence > b.evidence; });
    const Solution own = solution();
    const auto t0 = Clock::now();
    std::vector<Candidate> kept;
    int& dropped = track_dropped_;
    int& over_budget = track_over_budget_;
    for (Candidate& c : hypotheses_) {
        if (msSince(t0) > rp.track_max_ms) {
            ++over_budget;
            continue;
        }
        // Motion since the candidate's frame, body frame: the IMU preintegrated from the
        // candidate's own state once its velocity is measured, else odom_alt's delta, else the
        // IMU with the velocity unknown (rotation right, translation off by v dt: the coarse
        // start absorbs it), else the candidate's constant velocity, else none.
        const double tc = c.state.t;
        const SE3d T_c = c.state.T_map_imu();
        imu::Preintegration pre(c.state.bias(), imu::ImuNoise{params_.imu.acc_noise, params_.imu.gyro_noise});
        const bool imu_ok = params_.loc.use_imu && scan.t > tc && imu::coversInterval(sensors_.imu(), tc, scan.t, 0.05) &&
                            imu::integrateInterval(sensors_.imu(), tc, scan.t, pre) > 0;
        const auto odom = sensors_.odomAltDelta(tc, scan.t);
        SE3d T_pred = T_c;
        bool imu_predicted = false;
        const bool measured = imu_ok || odom.has_value();
        if (imu_ok && c.has_velocity) {
            T_pred = pre.predict(c.state.nav(), c.state.bias(), g_map_).pose();
            imu_predicted = true;
        } else if (odom) {
            T_pred = T_c * *odom;
        } else if (imu_ok) {
            T_pred = pre.predict(imu::NavState::fromPose(T_c), c.state.bias(), g_map_).pose();
        } else if (c.T_map_imu_before && tc > c.t_before) {
            const Vec6d xi = toVec6(c.T_map_imu_before->inverse() * T_c) / (tc - c.t_before);
            T_pred = T_c * fromVec6(xi * (scan.t - tc));
        }
        // Refined as a hypothesis of the search is verified (voxel map from its 1 m level, no
        // prior), inliers measured as tracking measures them.
        fusion::FrameState start = c.state;
        start.setPose(T_pred);
        FrameReport base = rep;
        base.used_imu = imu_predicted;
        base.T_map_lidar_pred = T_pred * scan.T_imu_lidar;
        FrameReport r = refineHypothesis(scan, start, base);
        HealthChecks checks;
        std::string why;
        const Health h = health_.classify(r, &why, &checks);
        const Vec3d& x = r.T_map_lidar.translation();
        MRPT_LOG_DEBUG_FMT("candidate (evidence %.3f over %d) -> (%.2f %.2f %.2f), moved %.2f m from its prediction, "
                           "inliers %.3f, %s %s",
                           c.evidence, c.frames, x.x(), x.y(), x.z(), r.pred_dxyz, r.inlier_ratio, healthName(h),
                           why.c_str());
        // Dropped when it no longer explains the scan: lost, or fitting clearly worse than
        // tracking fits on this map (the run's reference).
        if (h == Health::Lost || checks.badFit()) {
            ++dropped;
            ++track_judged_;
            continue;
        }
        // Its velocity at this frame: with the IMU, the one that carries the candidate from its
        // last pose to the refined one over the preintegrated interval (Forster eq. 33 solved
        // for v_i), then moved on by the IMU's delta velocity.
        const SE3d T_new = cur_.T_map_imu();
        const double dt = scan.t - tc;
        Vec3d v = Vec3d::Zero();
        if (imu_ok && dt > 0) {
            const Mat3d& Ri = T_c.linear();
            const Vec3d vi = (T_new.translation() - T_c.translation() - 0.5 * g_map_ * dt * dt -
                              Ri * pre.correctedDeltaP(c.state.bias())) /
                             dt;
            v = vi + g_map_ * dt + Ri * pre.correctedDeltaV(c.state.bias());
        } else if (dt > 0) {
            v = (T_new.translation() - T_c.translation()) / dt;
        }
        c.T_map_imu_before = T_c;
        c.t_before = tc;
        c.state = cur_;
        c.state.setVelocity(v);
        c.has_velocity = imu_ok && dt > 0;
        c.evidence += r.inlier_ratio;
        c.history.push_back(r.inlier_ratio);
        ++c.frames;
        c.rep = r;
        c.checks = checks;
        for (int k = 0; k < 3; ++k) c.axis_held[k] = !checks.weak[k] || (measured && c.axis_held[k]);
        c.corr = corr_;
        c.stats = last_stats_;
        kept.push_back(std::move(c));
    }
    track_ms_ = msSince(t0);
    rep.ms.solve += track_ms_;
    // Candidates that converged onto the same pose are one (the better evidence stays).
    std::sort(kept.begin(), kept.end(), [](const Candidate& a, const Candidate& b) { return a.evidence > b.evidence; });
    hypotheses_.clear();
    for (Candidate& c : kept) {
        const bool same = std::any_of(hypotheses_.begin(), hypotheses_.end(), [&](const Candidate& o) {
            return rp.samePlace(c.rep.T_map_lidar, o.rep.T_map_lidar);
        });
        if (!same) hypotheses_.push_back(std::move(c));
    }
    restore(own);
}

bool Localizer::weakAxesHeld(const Scan& scan, const Candidate& c) {
    // A translation the scan constrains weakly (gamma below weak_gamma: the risk, before the
    // solve) may still be held at the scale of the candidates: probe it. The candidate is moved
    // track_probe_xyz along each weak axis, both ways, and refined again; the axis is held when
    // every probe comes back (within max_pred_xyz) or fits clearly worse (under track_ratio x
    // the candidate's inlier ratio). Along a featureless corridor a probe stays where it was put
    // and fits as well: not held.
    const auto& rp = params_.relocalization;
    const Solution own = solution();
    bool held = true;
    const SE3d T_c = c.state.T_map_imu();
    for (int k = 0; k < 3 && held; ++k) {
        if (!c.checks.weak[k]) continue;
        for (const double sign : {-1.0, 1.0}) {
            fusion::FrameState start = c.state;
            start.setPose(SE3d(Eigen::Translation3d(T_c.linear().col(k) * sign * rp.track_probe_xyz)) * T_c);
            const FrameReport r = refineHypothesis(scan, start, c.rep);
            const double back = translationDistance(r.T_map_lidar, c.rep.T_map_lidar);
            const bool worse = r.diverged || r.inlier_ratio < rp.track_ratio * c.rep.inlier_ratio;
            MRPT_LOG_DEBUG_FMT("  probe %s%c %.1f m: back to %.2f m, inliers %.3f vs %.3f", sign < 0 ? "-" : "+",
                               "xyz"[k], rp.track_probe_xyz, back, r.inlier_ratio, c.rep.inlier_ratio);
            if (!(back <= params_.health.max_pred_xyz || worse)) {
                held = false;
                break;
            }
        }
    }
    restore(own);
    return held;
}

RelocOutcome Localizer::decideCandidates(const Scan& scan, FrameReport& rep) {
    const auto& rp = params_.relocalization;
    const double ref = health_.reference();
    // What a search on this frame did (merged its hypotheses into the set), if one ran.
    const RelocReport searched = rep.reloc;
    RelocReport rr;
    rr.mode = "track";
    rr.trigger = candidates_trigger_;
    rr.outcome = RelocOutcome::Failed;
    rr.hypotheses = searched.hypotheses;
    rr.search_ms = searched.search_ms;
    rr.verify_ms = searched.verify_ms + track_ms_;
    const auto report = [&](FrameReport& r) { r.reloc = rr; };
    const std::string budget = (track_over_budget_ ? mrpt::format("+over_budget:%d", track_over_budget_) : "") +
                               (searched.mode.empty() ? "" : "+search:" + std::string(relocOutcomeName(searched.outcome)));
    rr.verified = rr.candidates = static_cast<int>(hypotheses_.size());
    if (hypotheses_.empty()) {
        rr.detail = mrpt::format("candidates_dropped:%d", track_dropped_) + budget;
        report(rep);
        return rr.outcome;
    }
    // The best: the highest mean inlier ratio over its frames.
    const auto mean = [](const Candidate& c) { return c.evidence / c.frames; };
    std::stable_sort(hypotheses_.begin(), hypotheses_.end(),
                     [&](const Candidate& a, const Candidate& b) { return mean(a) > mean(b); });
    const Candidate& best = hypotheses_.front();
    for (const Candidate& c : hypotheses_) rr.alternatives.push_back(c.rep.T_map_lidar);
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
    std::vector<bool> ruled(hypotheses_.size(), false);
    for (size_t i = 1; i < hypotheses_.size(); ++i) {
        const Candidate& a = hypotheses_[i];
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
        MRPT_LOG_DEBUG_FMT("  vs candidate at (%.2f %.2f), %zu frames, last %.3f vs %.3f: ratio %.3f, best ahead on %zu "
                           "of %zu%s",
                           a.rep.T_map_lidar.translation().x(), a.rep.T_map_lidar.translation().y(), a.history.size(),
                           a.history.back(), best.history.back(), ratio, ahead, common, ruled_out ? ": ruled out" : "");
        margin = margin && ruled_out;
        ruled[i] = ruled_out;
    }
    rr.evidence_ratio = worst_ratio;
    MRPT_LOG_DEBUG_FMT("best candidate at (%.2f %.2f), %zu frames, mean %.3f", best.rep.T_map_lidar.translation().x(),
                       best.rep.T_map_lidar.translation().y(), best.history.size(), mean(best));
    // A hypothesis of this frame's search that found no place in the full set was not judged.
    margin = margin && !track_left_out_;
    // ...and something was told apart: another candidate ruled out here, or one dropped on the
    // way. A lone candidate never compared with anything is no evidence (simulated cave: a lone
    // pose 89 m off, inlier ratio 0.40, survived two frames).
    const bool compared = hypotheses_.size() > 1 || track_judged_ > 0;
    const bool ready = fit_ok && margin && compared && best.frames >= rp.track_min_frames;
    const bool held = carried || (ready && weakAxesHeld(scan, best));
    if (!(ready && held)) {
        // Candidates ruled out stay tracked (the next searches find their places again: a
        // judged place must not come back as a new, unjudged candidate), but yield their places
        // in the set to new ones when it is full.
        for (size_t i = 0; i < hypotheses_.size(); ++i) hypotheses_[i].ruled_out = ruled[i];
        rr.outcome = RelocOutcome::Ambiguous;
        rr.detail = mrpt::format("candidates:%zu", hypotheses_.size()) + (fit_ok ? "" : "+unhealthy") + (held ? "" : "+weak") + (compared ? "" : "+alone") +
                    (margin ? "" : mrpt::format("+margin:%.3f", rr.evidence_ratio)) +
                    (track_left_out_ ? "+full" : "") + budget;
        // Lost all the same, reporting the best candidate's pose.
        rep.T_map_lidar = best.rep.T_map_lidar;
        rep.T_map_imu = best.rep.T_map_imu;
        report(rep);
        if (candidates_age_ >= rp.track_max_frames) {
            // Not settled in that many frames: the right pose may not be in the set at all.
            hypotheses_.clear();
            rep.reloc.detail += "+expired";
            rep.reloc.candidates = 0;
        }
        return rr.outcome;
    }
    restore({best.state, best.corr, best.stats, best.rep.T_map_lidar});
    rr.outcome = RelocOutcome::Accepted;
    rr.detail = mrpt::format("frames:%d", best.frames) + budget;
    const StageTimes ms = rep.ms;
    rep = best.rep;
    rep.ms = ms;
    report(rep);
    rep.recovered = true;
    restart_ = true;  // the next frame starts coarse, as after any relocalization of a lost frame
    MRPT_LOG_INFO_FMT("frame %zu (t=%.3f): relocalized by tracking %zu candidates over %d frames (evidence ratio %.3f, "
                      "%.0f ms), inlier ratio %.2f",
                      rep.index, rep.t, hypotheses_.size(), best.frames, rr.evidence_ratio, rr.verify_ms,
                      rep.inlier_ratio);
    hypotheses_.clear();
    return rr.outcome;
}

}  // namespace superloc::localization
