// TrackReport (frame_report.h): the risk step's per-frame results.
#include <superloc/core/se3.h>
#include <superloc/localization/frame_report.h>

namespace superloc::localization {

void TrackReport::setRisk(const risk::RiskReport& r) {
    gamma = r.gamma;
    degenerate = r.degenerate;
    degenerate_axes = risk::degenerateAxes(r);
    flags_labels1 = risk::axisLetters(r.rules.labels1);
    flags_labels2 = risk::axisLetters(r.rules.labels2);
    flags_eigen = risk::axisLetters(r.rules.eigen);
    hessian_eigenvalues = r.weight_sum > 0 ? Vec6d(r.eigenvalues / r.weight_sum) : Vec6d::Zero();
    translation_eigenvalues = r.translation_eigenvalues;
    weakest_translation = r.weakest_translation;
}

void FrameReport::measurePrediction() {
    pred_dxyz = translationDistance(T_map_lidar, T_map_lidar_pred);
    pred_ddeg = rotationAngle(T_map_lidar, T_map_lidar_pred) / kDeg;
}

}  // namespace superloc::localization
