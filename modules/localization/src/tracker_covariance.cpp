// The Tracker's covariance of a frame's pose (tracker.h, doc/method.md §4): the posterior of the
// solve, without its scan for a frame in doubt, plus what the sweep's undone motion leaves.
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/localization/tracker.h>

#include <cmath>

namespace superloc::localization {

namespace {
using Clock = SteadyClock;
/// The share of the scan's translation information that its normals' noise puts on every
/// direction ([risk] normal_noise_deg: informationAboveNoise's floor).
double noiseFloorShare(const LocalizerParams& p) { return std::pow(std::sin(p.risk.normal_noise_deg * kDeg), 2); }
}  // namespace

void Tracker::scanCovariance(FrameSolution& sol) const {
    TrackReport& rep = sol.report;
    const auto t0 = Clock::now();
    const Mat6d H = fusion::informationAboveNoise(
        fusion::scanInformation(sol.corr, sol.state.T_map_imu(), params_.fusion.scan_sigma), noiseFloorShare(params_));
    rep.cov = post_.covariance(H, fusion::FloorGeometry(H));
    rep.ms.risk += msSince(t0);
}

void Tracker::posterior(const Frame& f, FrameSolution& sol) const {
    // Timed with the risk stage, as scanCovariance() and the estimate's information are.
    const auto t0 = Clock::now();
    // The IMU chain as it really errs, odom_alt at what it is worth (pose_posterior.h).
    EstimateWindow w(f.prev, sol.state, f.pred.used_imu && !f.first ? &f.pre : nullptr, params_);
    fusion::FrameProblemInputs& in = w.in;
    // odom_alt's prior as the solve weighed it, with what it is worth (PosePosterior::update).
    if (sol.prior && !f.first) in.prior = *sol.prior;
    // The scan as the estimate adds it: nothing below the noise floor along a direction the
    // carried information leaves weak (EstimateInformation::scanPart, doc/method.md §4).
    fusion::FloorGeometry floor(sol.scan_info, deskewedAlongImu(f));
    const fusion::ActiveFusionParams& a = params_.fusion.active;
    if (a.cov_map_length > 0)
        floor.map_share = fusion::mapErrorShare(sol.corr, sol.state.T_map_imu(), a.cov_map_cell, a.cov_map_length,
                                                noiseFloorShare(params_));
    // Not along a direction carried beyond the association's reach that the risk says the scan
    // does not hold: what the scan says there may be an alias of the truth (an end wall coming
    // into view metres from where the drifted pose puts it; doc/method.md §4, "Beyond the
    // association's reach").
    fusion::ScanReach reach;
    reach.gamma = sol.report.gamma;
    reach.weak_gamma = params_.health.weak_gamma;
    reach.reach = params_.loc.max_corr_dist / 3.0;
    sol.post = post_.update(in, params_.fusion, sol.est_info ? sol.est_info->scanPart(sol.scan_info) : sol.scan_info,
                            floor, reach);
    sol.report.cov = sol.post->cov + sweepCovariance(f, sol);
    sol.report.ms.risk += msSince(t0);
}

Mat6d Tracker::dropScan(FrameSolution& sol) const {
    // Without its scan the pose is what was carried: the sweep's distortion of the scan is not in it.
    sol.post = post_.withoutScan(*sol.post);
    return sol.post->cov;
}

bool Tracker::deskewedAlongImu(const Frame& f) { return f.pred.twist_from_imu && !f.features.motion.empty(); }

fusion::SweepDeparture Tracker::sweepDeparture(const Frame& f, const fusion::FrameState& cur) const {
    // What the sweep's motion leaves undone (doc/method.md §4): deskewed along the IMU's
    // trajectory, nothing beyond the floor. Otherwise the points were placed along a path that
    // departs from the sensor's by delta g(s) (s in [0, 1] from the sweep's first point to its
    // last, the scan's time):
    // - not deskewed: the motion from the point's time to the scan's, the whole sweep's motion
    //   delta with g = 1 - s;
    // - deskewed with one constant twist from odom_alt: the motion's departure from it, which
    //   odom_alt's own samples show at mid-sweep (delta); a constant acceleration bends the path
    //   into a parabola through both ends, g = 4 s (1 - s) (a swaying sensor: 0.15 deg of pitch
    //   at 3 Hz);
    // - deskewed with the constant velocity of the last two frames: a wrong rate's error grows
    //   from the scan's time back over the sweep, delta the whole sweep's share of the change
    //   between that velocity and the solved one, g = 1 - s.
    // None where `[features] deskew = false` says the sweeps come motion-compensated (KITTI's
    // scans) or the points carry no times (ScanFeatures::sweep_s).
    fusion::SweepDeparture d;
    const double T = f.features.sweep_s, dt = cur.t - f.prev.t;
    if (f.first || f.pred.twist_from_imu || !(T > 0 && T < 1.0 && dt > 0)) return d;
    d.T = T;
    const Vec6d xi = toVec6(f.prev.T_map_imu().inverse() * cur.T_map_imu()) / dt;  // solved body twist
    if (f.features.motion.empty()) {
        d.delta = xi * T;
        return d;
    }
    if (f.pred.from_odom) {
        const auto half = sensors_.odomAltDelta(cur.t - T, cur.t - 0.5 * T), whole = sensors_.odomAltDelta(cur.t - T, cur.t);
        if (half && whole) {
            d.delta = toVec6(*half) - 0.5 * toVec6(*whole);
            d.parabola = true;
        }
        return d;
    }
    Vec6d pred;
    pred << f.pred.v_body, f.pred.w_body;
    d.delta = (xi - pred) * T;
    return d;
}

Mat6d Tracker::sweepCovariance(const Frame& f, const FrameSolution& sol) const {
    // Through the scan's geometry and its points' times (fusion::sweepCovariance, doc/method.md
    // §4 "The sweep"): in a corridor a swaying sensor's floor behind, seen at the sweep's ends,
    // and ahead, at its middle, tilt differently, and the fit answers with pitch *and* z.
    const fusion::SweepDeparture d = sweepDeparture(f, sol.state);
    if (d.none() || !sol.post) return Mat6d::Zero();
    return fusion::sweepCovariance(sol.corr, sol.state.T_map_imu(), d, params_.fusion.scan_sigma,
                                   noiseFloorShare(params_), sol.post->carriedPoseInformation());
}

}  // namespace superloc::localization
