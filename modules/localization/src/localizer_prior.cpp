// The Localizer's link to odom_alt (DESIGN §5): its relative motion and covariance over a frame,
// what the method's fusion policy (method_variant.h) sees of the frame, and the observability
// labels of the last frame's correspondences.
#include <superloc/core/se3.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/localization/localizer.h>

#include <algorithm>
#include <iterator>

namespace superloc::localization {

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
