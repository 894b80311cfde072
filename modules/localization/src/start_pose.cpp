// StartPose: the first frame's initial pose, resolved in one place (start_pose.h).
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/localization/start_pose.h>

#include <cmath>
#include <cstdio>
#include <limits>

namespace superloc::localization {

StartPose::Decision StartPose::give(const SE3d& T, const std::string& what, const map::PriorMap& map,
                                    bool can_search) {
    what_ = what;
    // Within the map's bounds grown by the sensor's range.
    Vec3f lo = Vec3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
    for (const auto& p : map.points()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const Vec3d t = T.translation();
    const Vec3d l = lo.cast<double>() - Vec3d::Constant(max_range_), h = hi.cast<double>() + Vec3d::Constant(max_range_);
    const bool finite = t.allFinite() && T.linear().allFinite();
    if (finite && (t.array() >= l.array()).all() && (t.array() <= h.array()).all()) {
        given_ = T;
        return Decision::Take;
    }
    given_.reset();
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s: position (%.6g, %.6g, %.6g) is outside the prior map (bounds [%.1f, %.1f] x [%.1f, %.1f] x "
                  "[%.1f, %.1f] m grown by features.max_range = %.0f m)",
                  what.c_str(), t.x(), t.y(), t.z(), lo.x(), hi.x(), lo.y(), hi.y(), lo.z(), hi.z(), max_range_);
    what_ = buf;
    if (params_.out_of_map == "global" && can_search) return Decision::Search;
    throw ConfigError(std::string(buf) + " (or set relocalization.out_of_map=global)");
}

void StartPose::giveTrajectory(const Trajectory& traj, const std::string& what) {
    if (traj.empty()) throw ConfigError(what + ": no pose in the TUM file");
    pending_traj_ = traj;
    what_ = what;
    given_.reset();
}

std::optional<StartPose::Decision> StartPose::atFirstScan(double t, const map::PriorMap& map, bool can_search,
                                                          bool& covered) {
    if (pending_traj_.empty()) return std::nullopt;
    const auto at = interpolateAt(pending_traj_, t, 1.0, 0.05);
    covered = at.has_value();
    const SE3d T = at ? *at : pending_traj_.front().pose;
    const std::string what = what_;
    pending_traj_.clear();
    return give(T, what, map, can_search);
}

std::vector<SE3d> StartPose::seeds(const SE3d& T0, const RelocalizationParams& rp) {
    const double r = rp.start_xyz * 2 / 3, yaw = rp.start_deg * 2 / 3 * kDeg;
    const auto seed = [&](const Vec3d& dx, double dyaw) {
        SE3d T = turnedAboutVertical(T0, dyaw);
        T.translation() += dx;
        return T;
    };
    std::vector<double> ring_yaws = {0.0};
    if (yaw > 0 && rp.start_ring_yaws == 3) ring_yaws.insert(ring_yaws.end(), {-yaw, yaw});
    std::vector<SE3d> out;
    if (yaw > 0)
        for (const double y : {-yaw, yaw}) out.push_back(seed(Vec3d::Zero(), y));
    if (r > 0)
        for (int k = 0; k < 6; ++k)
            for (const double y : ring_yaws)
                out.push_back(seed(Vec3d(r * std::cos(k * M_PI / 3), r * std::sin(k * M_PI / 3), 0), y));
    return out;
}

}  // namespace superloc::localization
