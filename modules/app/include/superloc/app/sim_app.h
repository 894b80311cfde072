// The `superloc-sim` application class: CONFIG.ini [--out DIR] [--seed N] [--set s.k=v]...
// Builds the world, moves the platform along its route and writes (through io)
//   DIR/sequence.rawlog  LiDAR sweeps, IMU, odom_alt and gt observations in time order
//   DIR/gt_tum.txt       T_map_lidar at every sweep time (end of sweep)
//   DIR/gt_map.ply       dense survey sampling of the surfaces near the trajectory
//   DIR/prior_map.pcd    the voxelized, noisy map a user would be given
//   DIR/topview.svg      top view of the world and trajectory; DIR/config.ini effective config
#pragma once

#include <mrpt/system/COutputLogger.h>
#include <superloc/sim/sim_config.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace superloc::app {

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
    void initialize(sim::SimConfig cfg, const std::string& out_dir);
    /// Generates all outputs; progress (0..1) is reported to `on_progress` when set.
    SimSummary run();

    static std::string usage();
    std::function<void(double)> on_progress;
    const sim::SimConfig& config() const { return cfg_; }
    const std::string& outDir() const { return out_dir_; }
    /// --dump-config was given: print effectiveConfig(config()) instead of running.
    bool dumpConfig() const { return dump_config_; }

 private:
    sim::SimConfig cfg_;
    std::string out_dir_ = "sim-out";
    bool dump_config_ = false;
};

}  // namespace superloc::app
