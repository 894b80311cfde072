// method = eigen_remap: Zhang, Kaess, Singh, "On degeneracy of optimization-based state
// estimation problems", ICRA 2016 — solution remapping, the DESIGN §6 baseline of SuperLoc.
// After each round's solve, the update is projected onto the eigen-directions of the scan
// Hessian whose eigenvalue is above [fusion] eigen_threshold; along the others the pose comes
// from odom_alt (previous pose * odom_alt motion) when it covers the frame, else it stays at the
// round's start pose (the IMU / constant-velocity prediction on the first round).
#include <superloc/core/se3.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/localization/localizer.h>

namespace superloc::localization {

void Localizer::remapUpdate(const fusion::FrameState& prev_saved, const SE3d& T_before,
                            const fusion::ScanFactor& scan, FrameReport& rep) {
    const SE3d T_solved = cur_.T_map_imu();
    // H at the solution with the round's IRLS weights, normalised by the total weight and
    // without sigma, so the threshold reads as information per correspondence.
    double wsum = 0;
    for (double w : scan.sqrtWeights()) wsum += w * w;
    if (!(wsum > 0)) return;
    const Mat6d H =
        fusion::scanInformation(scan.correspondences(), T_solved, 1.0, &scan.sqrtWeights()) / wsum;
    const auto delta = have_prev_ ? odomAltForFrame() : std::nullopt;
    const SE3d T_ref = delta ? SE3d(prev_saved.T_map_imu() * *delta) : T_before;
    const auto r = fusion::eigenRemap(T_ref, T_solved, H, params_.fusion.active.eigen_threshold);
    if (r.removed == 0) return;
    cur_.setPose(r.T);
    // Reported as a prior when odom_alt supplied the removed directions; prior_w_* = the share
    // of each axis in the removed subspace (diagonal of its projector, 0..1).
    rep.prior_used = delta.has_value();
    rep.prior_weight = delta ? r.prior_share : Vec6d::Zero();
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
