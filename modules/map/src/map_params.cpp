// [map] section: voxel filter of the loaded map and the neighbourhood used for normals.
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/map/prior_map.h>

#include <cmath>

namespace superloc::map {

void MapParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(voxel_size, double, c, s);
    MRPT_LOAD_CONFIG_VAR(normal_k, int, c, s);
    MRPT_LOAD_CONFIG_VAR(normal_max_radius, double, c, s);
}

void MapParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(voxel_size, "[m] voxel filter of the loaded map (0 = keep all)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(normal_k, "neighbours per point for normal/planarity (>= 3)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(normal_max_radius, "[m] farther neighbours are not used");
}

void MapParams::validate() const {
    if (!std::isfinite(voxel_size) || voxel_size < 0)
        throw ConfigError("[map] voxel_size must be >= 0 m (0 keeps every point)");
    if (normal_k < 3 || normal_k > 200)
        throw ConfigError("[map] normal_k must be in [3, 200]");
    if (!std::isfinite(normal_max_radius) || normal_max_radius <= 0)
        throw ConfigError("[map] normal_max_radius must be > 0 m");
}

}  // namespace superloc::map
