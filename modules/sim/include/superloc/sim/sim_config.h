// The simulator's configuration (sections [sim] [trajectory] [lidar] [imu] [odom_alt] and one
// world section) and the scene it describes: what superloc-sim (modules/app) and the tests build
// a sequence from.
#pragma once

#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/sim/imu_model.h>
#include <superloc/sim/lidar.h>
#include <superloc/sim/odom_alt.h>
#include <superloc/sim/sim_params.h>
#include <superloc/sim/trajectory.h>
#include <superloc/sim/worlds.h>

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

}  // namespace superloc::sim
