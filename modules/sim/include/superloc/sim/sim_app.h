// The `superloc-sim` application class: CONFIG.ini [--out DIR] [--seed N] [--set s.k=v]...
// Builds the world, moves the platform along its route and writes (through io)
//   DIR/sequence.rawlog  LiDAR sweeps, IMU, odom_alt and gt observations in time order
//   DIR/gt_tum.txt       T_map_lidar at every sweep time (end of sweep)
//   DIR/gt_map.ply       dense survey sampling of the surfaces near the trajectory
//   DIR/prior_map.pcd    the voxelized, noisy map a user would be given
//   DIR/topview.svg      top view of the world and trajectory; DIR/config.ini effective config
#pragma once

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/system/COutputLogger.h>
#include <superloc/sim/imu_model.h>
#include <superloc/sim/lidar.h>
#include <superloc/sim/odom_alt.h>
#include <superloc/sim/sim_params.h>
#include <superloc/sim/trajectory.h>
#include <superloc/sim/worlds.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace superloc::sim {

/// Everything a run needs, after parsing and validation.
struct SimConfig {
    SimParams sim;
    TrajectoryParams trajectory;
    LidarParams lidar;
    ImuParams imu;
    OdomAltParams odom_alt;
    mrpt::config::CConfigFileMemory ini;  ///< merged INI (world sections are read from it)
    std::string source;                   ///< the INI file name, for messages
};

/// Loads CONFIG (with --set overrides applied, and the [lidar] preset merged in under the
/// file's own [lidar] keys). Throws ConfigError, one line naming the file and key.
SimConfig loadSimConfig(const std::string& ini_path, const std::vector<std::string>& overrides);

/// The effective configuration as INI text: every key of [sim] [trajectory] [lidar] [imu]
/// [odom_alt] with units in comments (the preset merged in), plus the world sections as given.
std::string effectiveConfig(const SimConfig& cfg);

/// The world and the platform's motion of a configuration (what run() simulates; tests use it
/// to check the outputs against the exact trajectory).
struct SimScene {
    World world;
    DensePath path;
    SmoothTrajectory trajectory;
};
/// Builds the scene; ConfigError naming the file on a bad world section.
SimScene makeScene(const SimConfig& cfg);

/// What a run produced.
struct SimSummary {
    size_t scans = 0, points = 0, imu = 0, odom_alt = 0;
    size_t gt_map_points = 0, prior_map_points = 0, mesh_triangles = 0;
    double duration = 0;                     ///< [s] simulated
    double path_length = 0;                  ///< [m] travelled by the body
    double max_speed = 0, max_yaw_rate = 0;  ///< [m/s], [rad/s] of the trajectory
    /// Returns by the dominant axis (x, y, z, map frame) of the surface normal they hit: a
    /// crude picture of which directions the geometry constrains.
    std::array<size_t, 3> normal_axis = {0, 0, 0};
};

class SimApp : public mrpt::system::COutputLogger {
 public:
    SimApp();
    /// Parses the command line; false when --help was asked (usage() is then to be printed).
    /// Throws std::runtime_error / ConfigError with a one-line reason on bad arguments.
    bool initialize(int argc, const char* const* argv);
    /// Or set up directly (tests).
    void initialize(SimConfig cfg, const std::string& out_dir);
    /// Generates all outputs; progress (0..1) is reported to `on_progress` when set.
    SimSummary run();

    static std::string usage();
    std::function<void(double)> on_progress;
    const SimConfig& config() const { return cfg_; }
    const std::string& outDir() const { return out_dir_; }
    /// --dump-config was given: print effectiveConfig(config()) instead of running.
    bool dumpConfig() const { return dump_config_; }

 private:
    SimConfig cfg_;
    std::string out_dir_ = "sim-out";
    bool dump_config_ = false;
};

}  // namespace superloc::sim
