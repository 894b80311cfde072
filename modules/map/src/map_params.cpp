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
    MRPT_LOAD_CONFIG_VAR(reg_voxel, double, c, s);
    MRPT_LOAD_CONFIG_VAR(reg_levels, int, c, s);
    MRPT_LOAD_CONFIG_VAR(reg_overlap, double, c, s);
    MRPT_LOAD_CONFIG_VAR(reg_min_points, int, c, s);
    MRPT_LOAD_CONFIG_VAR(tile_radius, double, c, s);
    MRPT_LOAD_CONFIG_VAR(tile_reload, double, c, s);
    MRPT_LOAD_CONFIG_VAR(geometry_at_load, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(grid_cell, double, c, s);
}

void MapParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(voxel_size, "[m] voxel filter of the loaded map (0 = keep all)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(normal_k, "neighbours per point for normal/planarity (>= 3)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(normal_max_radius, "[m] farther neighbours are not used");
    MRPT_SAVE_CONFIG_VAR_COMMENT(reg_voxel, "[m] registration voxel map: finest voxel edge");
    MRPT_SAVE_CONFIG_VAR_COMMENT(reg_levels, "registration voxel map: levels, each 2x coarser");
    MRPT_SAVE_CONFIG_VAR_COMMENT(reg_overlap, "[-] voxel dilation per side, fraction of the edge");
    MRPT_SAVE_CONFIG_VAR_COMMENT(reg_min_points, "voxels with fewer map points are dropped");
    MRPT_SAVE_CONFIG_VAR_COMMENT(tile_radius, "[m] tiled map: tiles within this x-y distance of the robot are loaded");
    MRPT_SAVE_CONFIG_VAR_COMMENT(tile_reload, "[m] tiled map: reload around the robot after moving this far");
    MRPT_SAVE_CONFIG_VAR_COMMENT(geometry_at_load, "every point's geometry computed at load on all cores (else by its first query)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(grid_cell, "[m] point grid of the planes association's fallback: cell edge (search radius <= 2 edges)");
}

void MapParams::validate() const {
    if (!std::isfinite(voxel_size) || voxel_size < 0)
        throw ConfigError("[map] voxel_size must be >= 0 m (0 keeps every point)");
    if (normal_k < 3 || normal_k > 200)
        throw ConfigError("[map] normal_k must be in [3, 200]");
    if (!std::isfinite(normal_max_radius) || normal_max_radius <= 0)
        throw ConfigError("[map] normal_max_radius must be > 0 m");
    if (!std::isfinite(reg_voxel) || reg_voxel < 0.05 || reg_voxel > 20)
        throw ConfigError("[map] reg_voxel must be in [0.05, 20] m");
    if (reg_levels < 1 || reg_levels > 6) throw ConfigError("[map] reg_levels must be in [1, 6]");
    if (!(reg_overlap >= 0 && reg_overlap < 0.5)) throw ConfigError("[map] reg_overlap must be in [0, 0.5)");
    if (reg_min_points < 3 || reg_min_points > 1000)
        throw ConfigError("[map] reg_min_points must be in [3, 1000]");
    if (!std::isfinite(tile_radius) || tile_radius <= 0) throw ConfigError("[map] tile_radius must be > 0 m");
    if (!std::isfinite(tile_reload) || tile_reload <= 0 || tile_reload >= tile_radius)
        throw ConfigError("[map] tile_reload must be > 0 m and < tile_radius");
    if (!std::isfinite(grid_cell) || grid_cell < 0.05 || grid_cell > 5)
        throw ConfigError("[map] grid_cell must be in [0.05, 5] m");
}

}  // namespace superloc::map
