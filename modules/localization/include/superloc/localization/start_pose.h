// Where the first frame starts (doc/health.md "Start"): the one place an initial pose is
// resolved, whatever gives it.
//   a pose     T_map_lidar (superloc-localize --initial-pose, a ROS node's initial pose)
//   a TUM file the pose interpolated at the first scan's time (--initial-pose-tum)
//   none       the map origin
// A given pose must lie where the map can be seen from: within the map's bounds grown by
// features.max_range; outside, a one-line ConfigError or ([relocalization] out_of_map =
// global) the global search instead. A given pose is then checked within its uncertainty by the
// start check (Recovery::checkStart) from the seeds() around it.
#pragma once

#include <superloc/core/types.h>
#include <superloc/localization/relocalization.h>
#include <superloc/map/prior_map.h>

#include <optional>
#include <string>
#include <vector>

namespace superloc::localization {

class StartPose {
   public:
    StartPose(const RelocalizationParams& params, double max_range) : params_(params), max_range_(max_range) {}

    /// What to do with a pose given for the first scan.
    enum class Decision { Take, Search };
    /// A pose given for the first scan (`what` names it in errors). Take when within `map`'s
    /// bounds; outside, Search with out_of_map = global and `can_search`, else throws ConfigError.
    Decision give(const SE3d& T_map_lidar, const std::string& what, const map::PriorMap& map, bool can_search);
    /// A trajectory whose pose at the first scan's time is the initial pose (resolved by
    /// atFirstScan); `what` names it (the file) in errors and warnings.
    void giveTrajectory(const Trajectory& traj, const std::string& what);
    /// At the first scan (time t): a given trajectory's pose there (interpolated within 1 s, else
    /// its first pose: `covered` false), checked like give(). Nothing when no trajectory waits.
    std::optional<Decision> atFirstScan(double t, const map::PriorMap& map, bool can_search, bool& covered);

    /// The given pose (T_map_lidar), if any.
    const std::optional<SE3d>& given() const { return given_; }
    /// The first frame's pose: the given one, else the map origin.
    SE3d firstPose() const { return given_.value_or(SE3d::Identity()); }
    const std::string& what() const { return what_; }

    /// The start check's seeds around T0, covering its uncertainty ([relocalization] start_xyz,
    /// start_deg): a ring of six at two thirds of start_xyz (the registration's basin reaches
    /// the rest), each at the given yaw and (start_ring_yaws = 3) two thirds of start_deg either
    /// way, and the given position turned either way. Empty when both are 0.
    static std::vector<SE3d> seeds(const SE3d& T0, const RelocalizationParams& params);

   private:
    const RelocalizationParams& params_;
    double max_range_;
    std::optional<SE3d> given_;
    Trajectory pending_traj_;
    std::string what_;
};

}  // namespace superloc::localization
