// The Localizer's link to the alignment risk and the relative-pose prior (DESIGN §5): the risk
// inputs from the correspondences, odom_alt's relative motion, and the prior hook that the
// active-fusion methods (issue 5) fill in.
#include <superloc/core/se3.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/localization/localizer.h>

#include <algorithm>
#include <iterator>

namespace superloc::localization {

std::optional<SE3d> Localizer::odomAltDelta(double t0, double t1) const {
    const auto a = interpolateAt(odom_alt_, t0, 0.5, 1e-3);
    const auto b = interpolateAt(odom_alt_, t1, 0.5, 1e-3);
    if (!a || !b) return std::nullopt;
    return orthonormalize(a->inverse() * *b);
}

std::optional<Mat6d> Localizer::odomAltCovAt(double t) const {
    // Linear interpolation of the reported covariance between the samples around t.
    const auto it = std::lower_bound(odom_alt_.begin(), odom_alt_.end(), t,
                                     [](const PoseStamped& p, double tt) { return p.t < tt; });
    if (it == odom_alt_.end() || !it->cov) return std::nullopt;
    if (it == odom_alt_.begin() || it->t == t) return it->cov;
    const auto prev = std::prev(it);
    if (!prev->cov || !(it->t > prev->t)) return it->cov;
    const double f = (t - prev->t) / (it->t - prev->t);
    return Mat6d((1 - f) * *prev->cov + f * *it->cov);
}

std::optional<SE3d> Localizer::odomAltForFrame() const {
    const auto d = odomAltDelta(prev_.t, cur_.t);
    // Issue 5: say once when odom_alt is absent or a gap starts, and when it is back; the frame
    // goes on without the prior (its degenerate flags are still reported in frames.csv).
    if (!d && odom_alt_state_ >= 0) {
        if (odom_alt_.empty())
            MRPT_LOG_WARN_FMT(
                "t=%.3f: no odom_alt in the rawlog: %s runs without the relative-pose prior",
                cur_.t, methodName(method_));
        else
            MRPT_LOG_WARN_FMT(
                "t=%.3f: odom_alt does not cover %.3f..%.3f (gap or end): no prior until it does",
                cur_.t, prev_.t, cur_.t);
        odom_alt_state_ = -1;
    } else if (d && odom_alt_state_ < 0) {
        MRPT_LOG_INFO_FMT("t=%.3f: odom_alt available again", cur_.t);
        odom_alt_state_ = 1;
    } else if (d) {
        odom_alt_state_ = 1;
    }
    return d;
}

std::optional<fusion::RelativePosePrior> Localizer::activePrior(
    const risk::RiskReport& risk) const {
    // icp and ndt use no prior; eigen_remap uses odom_alt in remapUpdate() instead of a factor.
    if (method_ != Method::SuperLoc && method_ != Method::Passive) return std::nullopt;
    if (!have_prev_) return std::nullopt;  // first frame: no previous state
    const auto delta = odomAltForFrame();
    if (!delta) return std::nullopt;
    const auto& ap = params_.fusion.active;
    Vec6d W;
    if (method_ == Method::Passive) {
        W = fusion::passiveInformation(ap);
    } else {
        // DESIGN §5 / paper §III-C: W = diag(max(0, 1 - gamma_k)) s_k, s_k = the mean scan
        // information per axis of the group, at the predicted pose (doc/method.md §2).
        const Mat6d H = fusion::scanInformation(corr_, cur_.T_map_imu(), params_.fusion.scan_sigma);
        Vec6d s = ap.prior_scale * fusion::priorScale(H);
        // Never more than odom_alt itself claims over this frame (when it reports a covariance).
        if (ap.prior_cap_by_odom_cov) {
            const auto c0 = odomAltCovAt(prev_.t), c1 = odomAltCovAt(cur_.t);
            if (c0 && c1) s = fusion::capScale(s, fusion::odomIncrementSigma(*c0, *c1, ap));
        }
        W = fusion::activeInformation(risk.gamma, s);
        if (!(W.maxCoeff() > 0)) return std::nullopt;  // well constrained everywhere
    }
    fusion::RelativePosePrior p;
    p.delta = *delta;
    p.sqrt_info = fusion::sqrtInfo(W);
    return p;
}

}  // namespace superloc::localization
