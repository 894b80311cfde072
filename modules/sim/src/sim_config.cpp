// Loading and validating the simulator's INI (sections [sim] [trajectory] [lidar] [imu]
// [odom_alt] and one world section), with --set overrides and the [lidar] preset file.
#include <superloc/core/config.h>
#include <superloc/sim/sim_config.h>
#include <superloc/sim/worlds.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace superloc::sim {
namespace {

// Prefixes a section-only validate() message with the file name.
template <class P>
P load(const mrpt::config::CConfigFileBase& cfg, const std::string& sect,
       const std::string& source) {
    try {
        return loadParams<P>(cfg, sect, source);
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        if (msg.rfind(source, 0) == 0) throw;
        throw ConfigError(source + ": " + msg);
    }
}

}  // namespace

SimConfig loadSimConfig(const std::string& ini_path, const std::vector<std::string>& overrides) {
    SimConfig c;
    c.source = ini_path;
    loadIniFile(c.ini, ini_path);
    for (const auto& o : overrides) applyOverride(c.ini, o);

    IniSections known{"superloc-sim", {"sim", "trajectory", "lidar", "imu", "odom_alt"}, {}, {}};
    known.reads.insert(known.reads.end(), worldNames().begin(), worldNames().end());
    checkSections(c.ini, known, ini_path, overrides);

    c.sim = load<SimParams>(c.ini, "sim", ini_path);
    for (const auto& w : worldNames())
        if (c.ini.sectionExists(w)) {
            try {
                validateWorldSection(w, c.ini, ini_path);
            } catch (const ConfigError& e) {
                const std::string msg = e.what();
                throw ConfigError(msg.rfind(ini_path, 0) == 0 ? msg : ini_path + ": " + msg);
            }
        }
    if (std::find(worldNames().begin(), worldNames().end(), c.sim.world) == worldNames().end())
        throw ConfigError(ini_path + ": [sim] world = '" + c.sim.world +
                          "' is unknown (corridor, cave, multifloor, openfield, office)");
    c.trajectory = load<TrajectoryParams>(c.ini, "trajectory", ini_path);
    c.imu = load<ImuParams>(c.ini, "imu", ini_path);
    c.odom_alt = load<OdomAltParams>(c.ini, "odom_alt", ini_path);

    // [lidar]: the preset's keys first, then this file's own keys on top.
    validateSection(c.ini, "lidar", LidarParams(), ini_path);
    const std::string preset = stripIniValue(c.ini.read_string("lidar", "preset", ""));
    mrpt::config::CConfigFileMemory lidar_ini;
    if (!preset.empty()) {
        std::filesystem::path pp(preset);
        if (pp.is_relative()) pp = std::filesystem::path(ini_path).parent_path() / pp;
        if (!std::filesystem::exists(pp))
            throw ConfigError(ini_path + ": [lidar] preset = '" + preset + "': file not found (" +
                              pp.string() + ")");
        loadIniFile(lidar_ini, pp.string(), "the LiDAR preset");
        validateSection(lidar_ini, "lidar", LidarParams(), pp.string());
    }
    std::vector<std::string> keys;
    c.ini.getAllKeys("lidar", keys);
    for (const auto& k : keys) lidar_ini.write("lidar", k, c.ini.read_string("lidar", k, ""));
    c.lidar = load<LidarParams>(lidar_ini, "lidar", ini_path);
    return c;
}

std::string effectiveConfig(const SimConfig& c) {
    mrpt::config::CConfigFileMemory eff;
    c.sim.saveToConfigFile(eff, "sim");
    c.trajectory.saveToConfigFile(eff, "trajectory");
    LidarParams lidar = c.lidar;
    lidar.preset.clear();  // its keys are all written here
    lidar.saveToConfigFile(eff, "lidar");
    c.imu.saveToConfigFile(eff, "imu");
    c.odom_alt.saveToConfigFile(eff, "odom_alt");
    std::string text =
        "# superloc-sim: effective configuration of " + c.source + "\n" + eff.getContent();
    // World sections as given (their Params are built and checked by the world builders).
    for (const auto& w : worldNames()) {
        if (!c.ini.sectionExists(w)) continue;
        std::vector<std::string> keys;
        c.ini.getAllKeys(w, keys);
        text += "\n[" + w + "]\n";
        for (const auto& k : keys)
            text += stripIniValue(k) + " = " + stripIniValue(c.ini.read_string(w, k, "")) + "\n";
    }
    return text;
}

SimScene makeScene(const SimConfig& c) {
    World world;
    try {
        world = buildWorld(c.sim.world, c.ini, c.source, c.sim.seed, c.trajectory.body_height);
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        throw ConfigError(msg.rfind(c.source, 0) == 0 ? msg : c.source + ": " + msg);
    }
    DensePath path = makeDensePath(world.route, c.trajectory.limits());
    SmoothTrajectory traj(path, c.trajectory, c.sim.start_time, c.sim.duration);
    return SimScene{std::move(world), std::move(path), std::move(traj)};
}

}  // namespace superloc::sim
