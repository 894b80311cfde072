// The Localizer: the map-based LiDAR-inertial localizer the apps and tests drive, one scan at a
// time (doc/localizer.md, "Structure"). A thin façade over the parts that do the work:
//   StartPose      where the first frame starts (start_pose.h)
//   Tracker        one frame: prediction, features, registration + fusion, a FrameSolution (tracker.h)
//   HealthMonitor  the frame's health, from the evidence the others hand it (health.h)
//   Recovery       the start check, the search of a lost or doubtful frame, the candidates of a
//                  frame without a pose, each verifying poses the same way (recovery.h)
//   SensorHistory  the IMU and odom_alt between scans (sensor_history.h)
#pragma once

#include <mrpt/system/COutputLogger.h>
#include <superloc/localization/frame_outputs.h>
#include <superloc/localization/frame_report.h>
#include <superloc/localization/health.h>
#include <superloc/localization/localizer_params.h>
#include <superloc/localization/method_variant.h>
#include <superloc/localization/recovery.h>
#include <superloc/localization/sensor_history.h>
#include <superloc/localization/start_pose.h>
#include <superloc/localization/tracker.h>
#include <superloc/map/prior_map.h>
#include <superloc/reloc/global_search.h>

#include <memory>
#include <optional>
#include <string>

namespace superloc::localization {

class NdtAligner;

/// A prior map with what the Localizer builds on it: the NDT grid (method ndt) and the global
/// search ([relocalization] enabled). Localizer::prepareMap makes one, e.g. in another thread
/// while frames go on; Localizer::setMap swaps it in between frames.
struct PreparedMap {
    std::shared_ptr<const map::PriorMap> map;
    std::unique_ptr<NdtAligner> ndt;
    std::unique_ptr<reloc::GlobalSearch> search;
    PreparedMap();
    PreparedMap(PreparedMap&&) noexcept;
    PreparedMap& operator=(PreparedMap&&) noexcept;
    ~PreparedMap();
};

class Localizer : public mrpt::system::COutputLogger {
   public:
    /// Throws ConfigError for a method that is not available yet, or an empty map.
    Localizer(const LocalizerParams& params, std::shared_ptr<const map::PriorMap> map);
    ~Localizer() override;

    /// Pose of the LiDAR at the first scan (T_map_lidar; StartPose, start_pose.h); without one
    /// the first scan starts at the map origin. A pose outside the map's bounds (grown by
    /// features.max_range) throws ConfigError naming `what`, or with [relocalization]
    /// out_of_map = global asks for relocalize() instead (a warning says so).
    void setInitialPose(const SE3d& T_map_lidar, const std::string& what = "initial pose");
    /// The same from a trajectory (a TUM file named `what`): its pose interpolated at the first
    /// scan's time (its first pose, with a warning, when it does not cover that time). The
    /// first process() then throws ConfigError when the pose is outside the map's bounds.
    void setInitialPose(const Trajectory& traj, const std::string& what);
    /// The next scan is localized without a pose (doc/health.md): by the global search in the
    /// whole map, or in `region` when given, each hypothesis verified by the fine registration
    /// and the health checks. A scan that finds no unambiguous pose is reported lost and the
    /// next one tries again. For `--initial-pose auto`, a kidnap signalled from outside, or a
    /// "relocalize" service of a ROS node. Throws ConfigError when relocalization is disabled.
    void relocalize(const std::optional<reloc::SearchRegion>& region = std::nullopt);
    /// The global search over the map (built at construction when [relocalization] enabled).
    const reloc::GlobalSearch* globalSearch() const { return search_.get(); }
    /// Builds what `params` need on `map` (thread-safe: touches no Localizer). Throws
    /// ConfigError for an empty map.
    static PreparedMap prepareMap(const LocalizerParams& params, std::shared_ptr<const map::PriorMap> map);
    /// Replaces the prior map between frames (the tiles around the robot of a map::TiledMap):
    /// the next frames associate with the new map, its NDT grid and global search. The
    /// tracking state (pose, velocity, IMU, health) carries over. `prepared` must come from
    /// prepareMap with this Localizer's parameters.
    void setMap(PreparedMap&& prepared);
    /// prepareMap(params, map), then setMap.
    void setMap(std::shared_ptr<const map::PriorMap> map);
    /// Samples must come in time order, before the scans they precede.
    void addImu(const ImuSample& s);
    /// Second odometry (odom_alt) poses, kept for the relative-pose prior.
    void addOdomAlt(const PoseStamped& p);

    /// Runs the pipeline on one scan; never throws for bad data (see FrameReport::diverged).
    /// `out` (optional): what the run's outputs need of the frame (frame_outputs.h), computed
    /// from its result after the frame's time is taken, so that the time is the localization's.
    FrameReport process(const Scan& scan, FrameOutputs* out = nullptr);

    const LocalizerParams& params() const { return params_; }
    Method method() const { return params_.loc.method; }

   private:
    LocalizerParams params_;
    MethodVariant variant_;  ///< registration + odom_alt fusion policy of params_.loc.method
    SensorHistory sensors_;
    HealthMonitor health_;
    StartPose start_;
    Tracker tracker_;
    Recovery recovery_;
    OutputMaker outputs_;
    std::shared_ptr<const map::PriorMap> map_;
    std::unique_ptr<NdtAligner> ndt_;
    std::unique_ptr<reloc::GlobalSearch> search_;
    Frame frame_;  ///< the frame being processed (its buffers kept between frames)
    size_t frames_ = 0;
};

}  // namespace superloc::localization
