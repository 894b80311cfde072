// The odom_alt fusion policies of the method variants (method_variant.h, doc/design.md#6-method-variants).
#include <superloc/core/se3.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/localization/method_variant.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace superloc::localization {

namespace {
constexpr double kChi2Dof1P99 = 6.635;  ///< chi-square, 1 dof, 99 %

/// The axes the scan alone held in a final frame: there the estimate is the scan's, and no
/// odom_alt prior pulled it (superloc's prior lies along the estimate's weak directions only).
std::array<bool, 6> heldByScan(const FusionFrame& f) {
    const Mat6d Ps = f.scan.G * f.scan.G, Pe = f.est.G * f.est.G;
    std::array<bool, 6> held{};
    for (int k = 0; k < 6; ++k) held[k] = Ps(k, k) < 0.1 && Pe(k, k) < 0.1;
    return held;
}

fusion::OdomCalibrationParams calibrationParams(const fusion::ActiveFusionParams& p, bool apply_correction) {
    fusion::OdomCalibrationParams c;
    c.memory_m = p.calibration_memory_m;
    c.apply_correction = apply_correction;
    return c;
}
}  // namespace

RawOdomWorth::RawOdomWorth(const fusion::ActiveFusionParams& p) : raw_(calibrationParams(p, false)) {}

void RawOdomWorth::learn(const FusionFrame& f) {
    if (f.odom_delta) raw_.update(*f.odom_delta, f.T_prev_map_imu.inverse() * f.T_map_imu, heldByScan(f));
}

Mat6d RawOdomWorth::cap(const Vec6d& info, const SE3d& odom_delta) const {
    const Vec6d s = raw_.sigma(odom_delta);
    Vec6d w = info;
    for (int k = 0; k < 6; ++k)
        if (std::isfinite(s[k]) && s[k] > 0) w[k] = std::min(w[k], 1.0 / (s[k] * s[k]));
    return Mat6d(w.asDiagonal());
}

std::optional<fusion::RelativePosePrior> OdomFusionPassive::prior(const FusionFrame& f,
                                                                  const risk::RiskReport&) const {
    if (!f.odom_delta) return std::nullopt;
    fusion::RelativePosePrior p;
    p.delta = *f.odom_delta;
    const Vec6d info = fusion::passiveInformation(p_);
    p.sqrt_info = fusion::sqrtInfo(info);
    // The covariance takes odom_alt at no more than its raw motion has shown it is worth.
    p.worth = worth_.cap(info, *f.odom_delta);
    return p;
}

OdomFusionActive::OdomFusionActive(const fusion::ActiveFusionParams& p, const Vec6d& weak_sigma)
    : p_(p), weak_(weak_sigma), calib_(calibrationParams(p, true)) {}

std::optional<fusion::RelativePosePrior> OdomFusionActive::prior(const FusionFrame& f,
                                                                 const risk::RiskReport&) const {
    if (!f.odom_delta || !(f.est.G.squaredNorm() > 1e-12)) return std::nullopt;
    // What odom_alt is worth per axis: its calibrated residual, else what it reports, else the
    // passive prior's sigmas.
    Vec6d sigma = fusion::passiveInformation(p_).cwiseSqrt().cwiseInverse();
    // What it reports is read as an error that keeps its sign from where the scan last held
    // each axis (odomIncrementSigmaKeepingSign; doc/method.md §2, "Before the worth is measured").
    if (f.odom_cov_prev && f.odom_cov_cur)
        sigma = p_.odom_calibration
                    ? fusion::odomIncrementSigmaKeepingSign(*f.odom_cov_prev, *f.odom_cov_cur, p_,
                                                            f.odom_delta->translation().norm(), calib_.sinceHeld())
                    : fusion::odomIncrementSigma(*f.odom_cov_prev, *f.odom_cov_cur, p_);
    fusion::RelativePosePrior p;
    p.delta = *f.odom_delta;
    // What it is worth for the pose's covariance (OdomCalibration::sigma's `worth`: wider beyond
    // the longest block measured); NaN where not calibrated.
    Vec6d worth = Vec6d::Constant(std::numeric_limits<double>::quiet_NaN());
    if (p_.odom_calibration) {
        const Vec6d cal = calib_.sigma(*f.odom_delta, &worth);
        for (int k = 0; k < 6; ++k)
            if (std::isfinite(cal[k])) sigma[k] = cal[k];
        p.delta = calib_.correct(*f.odom_delta);
    }
    // The innovation test: odom_alt's (corrected) motion against the IMU-carried prediction's,
    // on the axes where the estimate is weak. Where they disagree beyond what both claim
    // (chi-square, 1 dof, 99 %), odom_alt is worth no more than the disagreement says.
    if (f.pred_motion_var) {
        const Vec6d nu = toVec6(p.delta.inverse() * (f.T_prev_map_imu.inverse() * f.T_map_imu));
        const Mat6d P = f.est.G * f.est.G;
        for (int k = 0; k < 6; ++k) {
            if (P(k, k) < 0.5) continue;
            const double s2 = sigma[k] * sigma[k], v = (*f.pred_motion_var)[k];
            if (nu[k] * nu[k] > kChi2Dof1P99 * (s2 + v)) sigma[k] = std::sqrt(std::max(s2, nu[k] * nu[k] - v));
        }
    }
    // ... applied along the directions where the estimate is weak, in proportion to how weak.
    const Vec6d w_odom = sigma.cwiseAbs2().cwiseInverse();
    const Mat6d W = f.est.G * w_odom.asDiagonal() * f.est.G;
    p.sqrt_info = fusion::sqrtInfo(W);
    // The pose's covariance takes it at what it is worth, where that is wider than what the
    // solve weighs (never surer than what the innovation test left).
    const Vec6d worth_sigma = sigma.cwiseMax(worth.unaryExpr([](double v) { return std::isfinite(v) ? v : 0.0; }));
    if (worth_sigma != sigma)
        p.worth = Mat6d(f.est.G * worth_sigma.cwiseAbs2().cwiseInverse().asDiagonal() * f.est.G);
    return p;
}

std::optional<SE3d> OdomFusionActive::motion(const SE3d& odom_delta) const {
    return p_.odom_calibration ? calib_.correct(odom_delta) : odom_delta;
}

void OdomFusionActive::frameDone(const FusionFrame& f) {
    if (!p_.odom_calibration || !f.odom_delta) return;
    // Learn only where the scan alone held the axis. Every frame: the unheld axes count the
    // travel since they were last held.
    calib_.update(*f.odom_delta, f.T_prev_map_imu.inverse() * f.T_map_imu, heldByScan(f));
}

std::optional<fusion::RelativePosePrior> OdomFusionPaper::prior(const FusionFrame& f,
                                                                const risk::RiskReport& risk) const {
    if (!f.odom_delta || !f.corr) return std::nullopt;
    // doc/method.md §2 / paper §III-C: W = diag(max(0, 1 - gamma_k)) s_k, s_k = the mean scan
    // information per axis of the group, at the predicted pose (doc/method.md §2).
    Vec6d s = p_.prior_scale * fusion::priorScale(f.scan_H);
    // Never more than odom_alt itself claims over this frame (when it reports a covariance).
    if (p_.prior_cap_by_odom_cov && f.odom_cov_prev && f.odom_cov_cur)
        s = fusion::capScale(s, fusion::odomIncrementSigma(*f.odom_cov_prev, *f.odom_cov_cur, p_));
    const Vec6d W = fusion::activeInformation(risk.gamma, s);
    if (!(W.maxCoeff() > 0)) return std::nullopt;  // well constrained everywhere
    fusion::RelativePosePrior p;
    p.delta = *f.odom_delta;
    p.sqrt_info = fusion::sqrtInfo(W);
    // W is the paper's weight (the scan's own information per axis), not what odom_alt is worth:
    // the pose's covariance takes odom_alt at no more than the per-frame std the passive prior
    // is configured with (passive_sigma_*), else a blind axis reports the scan's millimetres
    // while the odometry drifts metres (doc/method.md §4).
    // Nor more than odom_alt's raw motion has shown it is worth (RawOdomWorth).
    p.worth = worth_.cap(W.cwiseMin(fusion::passiveInformation(p_)), *f.odom_delta);
    return p;
}

RoundAmend OdomFusionEigenRemap::afterRound(const FusionFrame& f, const SE3d& T_round_start,
                                            const fusion::ScanFactor& scan, const SE3d& T_solved) const {
    RoundAmend a;
    a.T = T_solved;
    // H at the solution with the round's IRLS weights (sigma and scale drop out: each group is
    // divided by its trace in eigenRemap).
    double wsum = 0;
    for (double w : scan.sqrtWeights()) wsum += w * w;
    if (!(wsum > 0)) return a;
    const Mat6d H = fusion::scanInformation(scan.correspondences(), T_solved, 1.0, &scan.sqrtWeights());
    // The reference is the frame's motion prior: the previous pose moved by odom_alt's motion
    // over the frame (odom_alt plays the visual odometry's part in Zhang et al.'s system), else
    // the round's start (the IMU or constant-velocity prediction on the first round).
    const SE3d T_ref = f.odom_delta ? SE3d(f.T_prev_map_imu * *f.odom_delta) : T_round_start;
    const auto r = fusion::eigenRemap(T_ref, T_solved, H, p_.eigen_threshold);
    if (r.removed == 0) return a;
    // Reported as a prior when odom_alt supplied the removed directions; prior_w_* = the share
    // of each axis in the removed subspace (diagonal of its projector, 0..1).
    a.reports_prior = true;
    a.prior_used = f.odom_delta.has_value();
    a.prior_weight = f.odom_delta ? r.prior_share : Vec6d::Zero();
    a.T = r.T;
    return a;
}

MethodVariant makeMethodVariant(Method m, const fusion::FusionParams& params, const risk::RiskParams& risk) {
    MethodVariant v;
    switch (m) {
        case Method::Icp: v.fusion = std::make_unique<OdomFusionNone>(); break;
        case Method::Ndt:
            v.registration = RegistrationKind::Ndt;
            v.fusion = std::make_unique<OdomFusionNone>();
            break;
        case Method::Passive: v.fusion = std::make_unique<OdomFusionPassive>(params.active); break;
        case Method::SuperLoc: {
            Vec6d weak;
            weak << Vec3d::Constant(risk.weak_sigma_xyz), Vec3d::Constant(risk.weak_sigma_deg * M_PI / 180.0);
            v.fusion = std::make_unique<OdomFusionActive>(params.active, weak);
            break;
        }
        case Method::SuperLocPaper:
            v.fusion = std::make_unique<OdomFusionPaper>(params.active);
            break;
        case Method::EigenRemap: v.fusion = std::make_unique<OdomFusionEigenRemap>(params.active); break;
    }
    return v;
}

}  // namespace superloc::localization
