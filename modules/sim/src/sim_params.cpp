#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>
#include <superloc/core/config.h>
#include <superloc/sim/sim_params.h>

namespace superloc::sim {

void SimParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(world, string, c, s);
    seed = static_cast<uint64_t>(c.read_uint64_t(s, "seed", seed));
    MRPT_LOAD_CONFIG_VAR(duration, double, c, s);
    MRPT_LOAD_CONFIG_VAR(start_time, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gt_map_spacing, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gt_map_max_distance, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prior_map_voxel, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prior_map_noise, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prior_map_warp, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prior_map_max_distance, double, c, s);
    MRPT_LOAD_CONFIG_VAR(scan_every, int, c, s);
}

void SimParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(world, "corridor, cave, multifloor, openfield, office");
    c.write(s, "seed", static_cast<uint64_t>(seed), mrpt::config::MRPT_SAVE_NAME_PADDING(),
            mrpt::config::MRPT_SAVE_VALUE_PADDING(),
            "random parts of the world and all noise (--seed)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(duration, "[s] sequence length (shorter if the route ends first)");
    c.write(s, "start_time", mrpt::format("%.6f", start_time),
            mrpt::config::MRPT_SAVE_NAME_PADDING(), mrpt::config::MRPT_SAVE_VALUE_PADDING(),
            "[s] timestamp of the first sample (UNIX time)");  // full precision
    MRPT_SAVE_CONFIG_VAR_COMMENT(gt_map_spacing, "[m] survey-map surface sampling");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gt_map_max_distance,
                                 "[m] surveyed surfaces: this close to the path");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prior_map_voxel, "[m] voxel size of prior_map.pcd");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prior_map_noise, "[m] 1-sigma white mapping noise");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prior_map_warp, "[m] smooth mapping warp amplitude (~10 m scale)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prior_map_max_distance, "[m] prior map extent around the path");
    MRPT_SAVE_CONFIG_VAR_COMMENT(scan_every, "write one LiDAR revolution in N (IMU, odom_alt: all)");
}

void SimParams::validate() const {
    const auto need = [](bool ok, const char* what) {
        if (!ok) throw ConfigError(std::string("[sim] ") + what);
    };
    need(duration > 0 && duration <= 3600, "duration must be in (0, 3600] s");
    need(start_time > 0, "start_time must be > 0 (0 is MRPT's invalid timestamp)");
    need(gt_map_spacing >= 0.005 && gt_map_spacing <= 1, "gt_map_spacing must be in [0.005, 1] m");
    need(gt_map_max_distance > 0, "gt_map_max_distance must be > 0");
    need(prior_map_voxel >= 0.01 && prior_map_voxel <= 5, "prior_map_voxel must be in [0.01, 5] m");
    need(prior_map_noise >= 0 && prior_map_warp >= 0, "prior_map_noise/warp must be >= 0");
    need(prior_map_max_distance > 0, "prior_map_max_distance must be > 0");
    need(scan_every >= 1 && scan_every <= 10000, "scan_every must be in [1, 10000]");
}

}  // namespace superloc::sim
