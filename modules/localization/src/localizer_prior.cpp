// The Localizer's link to odom_alt (DESIGN §5): its relative motion and covariance over a frame,
// what the method's fusion policy (method_variant.h) sees of the frame, and the observability
// labels of the last frame's correspondences.
#include <superloc/core/se3.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/localization/localizer.h>

#include <algorithm>
#include <iterator>

namespace superloc::localization {

std::optional<SE3d> Localizer::odomAltForFrame() const {
    const auto d = sensors_.odomAltDelta(prev_.t, cur_.t);
    // Say once when odom_alt is absent or a gap starts, and when it is back; the frame
    // goes on without the prior (its degenerate flags are still reported in frames.csv).
    if (!d && odom_alt_state_ >= 0) {
        if (!sensors_.hasOdomAlt())
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

FusionFrame Localizer::fusionFrame(const SE3d& T_map_imu, const SE3d& T_prev_map_imu) const {
    FusionFrame f;
    f.corr = &corr_;
    f.T_map_imu = T_map_imu;
    f.T_prev_map_imu = T_prev_map_imu;
    if (have_prev_ && variant_.fusion->usesOdomAlt()) {  // first frame: no previous state
        f.odom_delta = odomAltForFrame();
        if (f.odom_delta && params_.fusion.active.prior_cap_by_odom_cov) {
            f.odom_cov_prev = sensors_.odomAltCovAt(prev_.t);
            f.odom_cov_cur = sensors_.odomAltCovAt(cur_.t);
        }
    }
    return f;
}

void Localizer::observabilityPoints(std::vector<Vec3f>& points, std::vector<int8_t>& labels) const {
    points.clear();
    labels.clear();
    if (corr_.empty()) return;
    const SE3d T = cur_.T_map_imu();
    risk::RiskParams rp = params_.risk;
    rp.hessian_eigen = false;
    const auto risk = risk::computeAlignmentRisk(corr_, T, T_imu_lidar_.translation(), rp);
    points.reserve(corr_.size());
    labels.reserve(corr_.size());
    for (size_t i = 0; i < corr_.size(); ++i) {
        points.push_back((T * corr_[i].p).cast<float>());
        labels.push_back(risk.translation_label[i]);
    }
}

}  // namespace superloc::localization
