// odom_alt in a tracked frame's solve (frame_fusion.h): the look-ups and the policy's two points.
#include <superloc/core/se3.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/localization/frame_fusion.h>

#include <cmath>

namespace superloc::localization {

std::optional<SE3d> OdomAltLink::delta(double t_prev, double t) {
    const auto d = sensors_.odomAltDelta(t_prev, t);
    // Say once when odom_alt is absent or a gap starts, and when it is back; the frame
    // goes on without the prior (its degenerate flags are still reported in frames.csv).
    using mrpt::system::LVL_INFO, mrpt::system::LVL_WARN;
    if (!d && state_ >= 0) {
        if (!sensors_.hasOdomAlt())
            log_.logFmt(LVL_WARN, "t=%.3f: no odom_alt in the rawlog: %s runs without the relative-pose prior", t,
                        methodName(method_));
        else
            log_.logFmt(LVL_WARN, "t=%.3f: odom_alt does not cover %.3f..%.3f (gap or end): no prior until it does",
                        t, t_prev, t);
        state_ = -1;
    } else if (d && state_ < 0) {
        log_.logFmt(LVL_INFO, "t=%.3f: odom_alt available again", t);
        state_ = 1;
    } else if (d) {
        state_ = 1;
    }
    return d;
}

FusionFrame OdomAltLink::frame(bool have_prev, const SE3d& T_map_imu, const SE3d& T_prev_map_imu, double t_prev,
                               double t) {
    FusionFrame f;
    f.T_map_imu = T_map_imu;
    f.T_prev_map_imu = T_prev_map_imu;
    f.dt = t - t_prev;
    if (have_prev && policy_.usesOdomAlt()) {  // first frame: no previous state
        f.odom_delta = delta(t_prev, t);
        if (f.odom_delta && params_.active.prior_cap_by_odom_cov) {
            f.odom_cov_prev = sensors_.odomAltCovAt(t_prev);
            f.odom_cov_cur = sensors_.odomAltCovAt(t);
        }
    }
    return f;
}

void OdomAltLink::frameDone(OdomFusion& policy, const FrameSolution& sol, const fusion::FrameState& prev) const {
    FusionFrame f;
    f.T_map_imu = sol.state.T_map_imu();
    f.T_prev_map_imu = prev.T_map_imu();
    f.odom_delta = sensors_.odomAltDelta(prev.t, sol.state.t);
    f.est = sol.est_weak;
    f.scan = sol.scan_weak;
    policy.frameDone(f);
}

std::optional<fusion::RelativePosePrior> FrameFusion::prior(const std::vector<Correspondence>& corr,
                                                            const SE3d& T_map_imu, const risk::RiskReport& risk,
                                                            FrameSolution& sol) {
    TrackReport& rep = sol.report;
    frame_.corr = &corr;
    // Where is the estimate weak without odom_alt? (doc/method.md §2)
    frame_.scan_H = fusion::scanInformation(corr, T_map_imu, fusion_.scan_sigma);
    const double n = risk_.normal_noise_deg * kDeg;
    sol.scan_info = fusion::informationAboveNoise(frame_.scan_H, std::pow(std::sin(n), 2));
    Vec6d weak;
    weak << Vec3d::Constant(risk_.weak_sigma_xyz), Vec3d::Constant(risk_.weak_sigma_deg * kDeg);
    frame_.scan = fusion::weakness(sol.scan_info, weak);
    frame_.est = fusion::weakness(sol.est_info ? sol.est_info->information(sol.scan_info) : sol.scan_info, weak);
    rep.scan_info = sol.scan_info.diagonal();
    rep.scan_sigma = frame_.scan.sigma;
    rep.est_sigma = frame_.est.sigma;
    // The frame's decision: `degenerate` is where the estimate is weak; the paper's scan-only
    // flags stay in flags_labels2 (and gamma).
    rep.degenerate = frame_.est.weak;
    rep.degenerate_axes = risk::axisLetters(rep.degenerate);
    sol.est_weak = frame_.est;
    sol.scan_weak = frame_.scan;
    frame_.T_map_imu = T_map_imu;
    frame_.pred_motion_var = sol.est_info ? sol.est_info->motionVariance(frame_.dt, T_map_imu.linear()) : std::nullopt;
    return policy_.prior(frame_, risk);
}

RoundAmend FrameFusion::afterRound(const SE3d& T_round_start, const fusion::ScanFactor& scan, const SE3d& T_solved) {
    frame_.T_map_imu = T_round_start;
    return policy_.afterRound(frame_, T_round_start, scan, T_solved);
}

}  // namespace superloc::localization
