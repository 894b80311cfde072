// CandidateTracker (candidates.h, doc/relocalization.md §4): the candidates of an ambiguous
// relocalization kept, moved by the measured motion and verified on every scan.
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/localization/candidates.h>

#include <algorithm>
#include <cmath>

namespace superloc::localization {
namespace {
using Clock = SteadyClock;
using mrpt::system::LVL_DEBUG;
}  // namespace

std::vector<const FrameReport*> CandidateTracker::reports() const {
    std::vector<const FrameReport*> out;
    for (const Candidate& c : set_) out.push_back(&c.rep);
    return out;
}

double CandidateTracker::refine(Frame& f, const FrameReport& rep, const HealthJudge& judge) {
    const auto& rp = params_.relocalization;
    const Scan& scan = *f.scan;
    const Vec3d g_map(0, 0, -params_.imu.gravity);
    ++age_;
    dropped_ = over_budget_ = 0;
    left_out_ = false;
    // Best evidence first: under the time budget the weakest are the ones left out.
    std::sort(set_.begin(), set_.end(), [](const Candidate& a, const Candidate& b) { return a.evidence > b.evidence; });
    const auto t0 = Clock::now();
    std::vector<Candidate> kept;
    for (Candidate& c : set_) {
        if (msSince(t0) > rp.track_max_ms) {
            ++over_budget_;
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
            T_pred = pre.predict(c.state.nav(), c.state.bias(), g_map).pose();
            imu_predicted = true;
        } else if (odom) {
            T_pred = T_c * *odom;
        } else if (imu_ok) {
            T_pred = pre.predict(imu::NavState::fromPose(T_c), c.state.bias(), g_map).pose();
        } else if (c.T_map_imu_before && tc > c.t_before) {
            const Vec6d xi = toVec6(c.T_map_imu_before->inverse() * T_c) / (tc - c.t_before);
            T_pred = T_c * fromVec6(xi * (scan.t - tc));
        }
        // Verified as a hypothesis of the search is (voxel map from its 1 m level, no prior),
        // inliers measured as tracking measures them.
        fusion::FrameState start = c.state;
        start.setPose(T_pred);
        FrameReport base = rep;
        base.used_imu = imu_predicted;
        base.T_map_lidar_pred = T_pred * scan.T_imu_lidar;
        Attempt a = verifier_.verify(f, start, base, VerifyAs::Hypothesis, judge);
        const FrameReport& r = a.rep;
        const Vec3d& x = r.T_map_lidar.translation();
        log_.logFmt(LVL_DEBUG,
                    "candidate (evidence %.3f over %d) -> (%.2f %.2f %.2f), moved %.2f m from its prediction, "
                    "inliers %.3f, %s %s",
                    c.evidence, c.frames, x.x(), x.y(), x.z(), r.pred_dxyz, r.inlier_ratio,
                    healthName(a.verdict.health), a.verdict.reason.c_str());
        // Dropped when it no longer explains the scan: lost, or fitting clearly worse than
        // tracking fits on this map (the run's reference).
        if (a.verdict.health == Health::Lost || a.verdict.checks.badFit()) {
            ++dropped_;
            ++judged_;
            continue;
        }
        // Its velocity at this frame: with the IMU, the one that carries the candidate from its
        // last pose to the refined one over the preintegrated interval (Forster eq. 33 solved
        // for v_i), then moved on by the IMU's delta velocity.
        const SE3d T_new = a.sol.state.T_map_imu();
        const double dt = scan.t - tc;
        Vec3d v = Vec3d::Zero();
        if (imu_ok && dt > 0) {
            const Mat3d& Ri = T_c.linear();
            const Vec3d vi = (T_new.translation() - T_c.translation() - 0.5 * g_map * dt * dt -
                              Ri * pre.correctedDeltaP(c.state.bias())) /
                             dt;
            v = vi + g_map * dt + Ri * pre.correctedDeltaV(c.state.bias());
        } else if (dt > 0) {
            v = (T_new.translation() - T_c.translation()) / dt;
        }
        c.T_map_imu_before = T_c;
        c.t_before = tc;
        c.state = a.sol.state;
        c.state.setVelocity(v);
        c.has_velocity = imu_ok && dt > 0;
        c.evidence += r.inlier_ratio;
        c.history.push_back(r.inlier_ratio);
        ++c.frames;
        c.checks = a.verdict.checks;
        for (int k = 0; k < 3; ++k) c.axis_held[k] = !c.checks.weak[k] || (measured && c.axis_held[k]);
        c.rep = std::move(a.rep);
        c.corr = std::move(a.sol.corr);
        c.stats = a.sol.stats;
        kept.push_back(std::move(c));
    }
    track_ms_ = msSince(t0);
    // Candidates that converged onto the same pose are one (the better evidence stays).
    std::sort(kept.begin(), kept.end(), [](const Candidate& a, const Candidate& b) { return a.evidence > b.evidence; });
    set_.clear();
    for (Candidate& c : kept) {
        const bool same = std::any_of(set_.begin(), set_.end(), [&](const Candidate& o) {
            return rp.samePlace(c.rep.T_map_lidar, o.rep.T_map_lidar);
        });
        if (!same) set_.push_back(std::move(c));
    }
    return track_ms_;
}

int CandidateTracker::admit(std::vector<Attempt> standing, const std::string& trigger) {
    // While candidates are tracked, the new ones (not already tracked) take the free places,
    // best fitting first: a tracked candidate is judged over its frames, not displaced by a
    // look-alike seen once (measured: the office's rooms replaced each other every frame).
    const auto& rp = params_.relocalization;
    const bool tracking = !set_.empty();
    if (!tracking) age_ = 0, judged_ = 0, outranked_frames_ = 0;
    bool outranked = false;
    double best_tracked = 0;
    for (const Candidate& c : set_) best_tracked = std::max(best_tracked, c.rep.inlier_ratio);
    std::sort(standing.begin(), standing.end(),
              [](const Attempt& a, const Attempt& b) { return a.rep.inlier_ratio > b.rep.inlier_ratio; });
    for (Attempt& o : standing) {
        const bool same = std::any_of(set_.begin(), set_.end(), [&](const Candidate& c) {
            return rp.samePlace(c.rep.T_map_lidar, o.rep.T_map_lidar);
        });
        if (same) continue;
        // While tracking: one that fits this scan clearly worse than the best tracked candidate
        // (under track_ratio x its inlier ratio) is no alternative.
        // It was told apart all the same: counted below as a frame on which the set outranked
        // another place.
        if (o.rep.inlier_ratio < rp.track_ratio * best_tracked) {
            outranked = true;
            continue;
        }
        if (static_cast<int>(set_.size()) >= rp.track_candidates) {
            // Full: the worst candidate already ruled out yields its place, else this
            // hypothesis is left out (and the frame commits nothing).
            auto worst = set_.end();
            for (auto it = set_.begin(); it != set_.end(); ++it)
                if (it->ruled_out &&
                    (worst == set_.end() || it->evidence / it->frames < worst->evidence / worst->frames))
                    worst = it;
            if (worst == set_.end()) {
                left_out_ = true;
                break;
            }
            set_.erase(worst);
            ++judged_;
        }
        Candidate c;
        c.state = o.sol.state;
        c.evidence = o.rep.inlier_ratio;
        c.history.push_back(o.rep.inlier_ratio);
        c.frames = 1;
        c.checks = o.verdict.checks;
        for (int k = 0; k < 3; ++k) c.axis_held[k] = !c.checks.weak[k];
        c.rep = o.rep;
        c.corr = o.sol.corr;
        c.stats = o.sol.stats;
        set_.push_back(std::move(c));
    }
    if (outranked) ++outranked_frames_;
    if (!tracking) trigger_ = trigger;
    return static_cast<int>(set_.size());
}

}  // namespace superloc::localization
