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
    const double r = rp.start_xyz * 2 / 3, yaw = rp.start_deg * 2 / 3 * kDeg;
    const auto seed = [&](const Vec3d& dx, double dyaw) {
        SE3d T = T0;
        T.translation() += dx;
        T.linear() = Eigen::AngleAxisd(dyaw, Vec3d::UnitZ()).toRotationMatrix() * T0.linear();
        return T;
    };
    std::vector<double> ring_yaws = {0.0};
    if (yaw > 0 && rp.start_ring_yaws == 3) ring_yaws.insert(ring_yaws.end(), {-yaw, yaw});
    std::vector<SE3d> seeds;
    if (yaw > 0)
        for (const double y : {-yaw, yaw}) seeds.push_back(seed(Vec3d::Zero(), y));
    if (r > 0)
        for (int k = 0; k < 6; ++k)
            for (const double y : ring_yaws)
                seeds.push_back(seed(Vec3d(r * std::cos(k * M_PI / 3), r * std::sin(k * M_PI / 3), 0), y));
    if (seeds.empty()) return;
    switch (runRelocalization(scan, pred, nullptr, rep, &seeds)) {
        case RelocOutcome::Accepted:
            assess(rep);
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
