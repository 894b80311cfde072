// The start check (doc/health.md, "Start"): the first frame from a given initial pose is solved
// again from seeds within that pose's uncertainty, and the relocalization's verification and
// ambiguity rules (localizer_relocalize.cpp, runRelocalization with seeds) decide between the
// results and the frame's own solve.
#include <superloc/core/se3.h>
#include <superloc/localization/localizer.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace superloc::localization {

std::vector<SE3d> Localizer::startBasins(const Scan& scan, const std::vector<SE3d>& seeds, const FrameReport& rep) {
    // Each seed solved in the voxel map (fast, as a search hypothesis); one pose per basin the
    // seeds reach, best first, kept where it fits at least start_refine_ratio x the best basin
    // (measured: refining every basin cost 919 ms on the KITTI split, these 219 ms).
    const auto& rp = params_.relocalization;
    std::vector<std::pair<SE3d, double>> basins;  // pose, inlier ratio
    for (const SE3d& T_seed : seeds) {
        fusion::FrameState start;
        start.setBias(prev_.bias());
        start.setPose(T_seed * scan.T_imu_lidar.inverse());
        const FrameReport r = refineHypothesis(scan, start, rep, Solve::Hypothesis);
        if (r.diverged) continue;
        const SE3d& T = r.T_map_lidar;
        if (std::none_of(basins.begin(), basins.end(), [&](const auto& b) { return rp.sameStartBasin(b.first, T); }))
            basins.emplace_back(T, r.inlier_ratio);
    }
    std::sort(basins.begin(), basins.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    std::vector<SE3d> tries;
    for (const auto& [T, ratio] : basins)
        if (ratio >= rp.start_refine_ratio * basins.front().second) tries.push_back(T);
    return tries;
}

void Localizer::verifyStart(const Scan& scan, const Prediction& pred, FrameReport& rep) {
    // Seeds covering the given pose's uncertainty: a ring of six at two thirds of start_xyz
    // (the registration's basin reaches the rest), each at the given yaw and (start_ring_yaws
    // = 3) two thirds of start_deg either way, and the given position turned either way.
    const auto& rp = params_.relocalization;
    const SE3d& T0 = *initial_T_map_lidar_;
    std::vector<SE3d> seeds;
    const double r = rp.start_xyz * 2 / 3, yaw = rp.start_deg * 2 / 3 * kDeg;
    for (int k = -1; k < (r > 0 ? 6 : 0); ++k)
        for (const double s : {0.0, -1.0, 1.0}) {
            const bool turned = s != 0;
            if ((k < 0 && !turned) || (turned && !(yaw > 0)) || (k >= 0 && turned && rp.start_ring_yaws == 1))
                continue;
            SE3d T = T0;
            if (k >= 0) T.translation() += Vec3d(r * std::cos(k * M_PI / 3), r * std::sin(k * M_PI / 3), 0);
            T.linear() = Eigen::AngleAxisd(s * yaw, Vec3d::UnitZ()).toRotationMatrix() * T0.linear();
            seeds.push_back(T);
        }
    if (seeds.empty()) return;
    switch (runRelocalization(scan, pred, nullptr, rep, &seeds)) {
        case RelocOutcome::Accepted:
            assess(rep);
            doubt_ = false;
            break;
        case RelocOutcome::Ambiguous:
            // Another result within the start's uncertainty fits about as well: the pose is
            // kept, but not as `ok`. (The frames after it are not held in doubt: on kitti00-mini
            // their searches took poses 0.4 m along the road, as the start's rivals were.)
            if (rep.health == Health::Ok) {
                rep.health = Health::Degraded;
                rep.health_reason = "start_ambiguous";
            }
            break;
        default: break;
    }
}

}  // namespace superloc::localization
