// OutputMaker: a frame's outputs from its result (frame_outputs.h).
#include <superloc/features/deskew.h>
#include <superloc/localization/frame_outputs.h>

namespace superloc::localization {

void OutputMaker::fill(const Scan& scan, const ScanFeatures& features, const FrameSolution& sol, FrameOutputs& out) {
    const SE3d T = sol.state.T_map_imu();
    out.map_points.clear();
    if (out.map_voxel > 0) {
        // The valid points, voxel-selected, deskewed like the features, at the solved pose.
        const SE3d T_map_lidar = T * scan.T_imu_lidar;
        selector_.select(scan.points, features.valid, static_cast<float>(out.map_voxel), idx_);
        features::deskewPoints(scan.points, scan.rel_time, idx_, features.motion, out.map_points);
        for (auto& p : out.map_points) p = (T_map_lidar * p.cast<double>()).cast<float>();
    }
    out.obs_points.clear();
    out.obs_labels.clear();
    if (!out.observability || sol.corr.empty()) return;
    const auto risk = risk::computeAlignmentRisk(sol.corr, T, scan.T_imu_lidar.translation(), risk_);
    out.obs_points.reserve(sol.corr.size());
    out.obs_labels.reserve(sol.corr.size());
    for (size_t i = 0; i < sol.corr.size(); ++i) {
        out.obs_points.push_back((T * sol.corr[i].p).cast<float>());
        out.obs_labels.push_back(risk.translation_label[i]);
    }
}

}  // namespace superloc::localization
