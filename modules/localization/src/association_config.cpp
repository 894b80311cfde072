// [association] section (association_config.h).
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/localization/association_config.h>

#include <cmath>

namespace superloc::localization {

AssociationKind associationKindFromString(const std::string& s) {
    if (s == "planes") return AssociationKind::Planes;
    if (s == "nearest") return AssociationKind::Nearest;
    if (s == "voxel") return AssociationKind::Voxel;
    throw ConfigError("[association] kind = '" + s + "' is unknown (use planes, nearest or voxel)");
}

const char* associationKindName(AssociationKind k) {
    switch (k) {
        case AssociationKind::Planes: return "planes";
        case AssociationKind::Nearest: return "nearest";
        case AssociationKind::Voxel: return "voxel";
    }
    return "?";
}

void AssociationConfig::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    kind = associationKindFromString(c.read_string(s, "kind", associationKindName(kind)));
    plane.min_points = c.read_int(s, "plane_min_points", plane.min_points);
    plane.thickness = c.read_double(s, "plane_thickness", plane.thickness);
    plane.min_spread = c.read_double(s, "plane_min_spread", plane.min_spread);
    plane.footprint = c.read_double(s, "plane_footprint", plane.footprint);
    plane.gate = c.read_double(s, "plane_gate", plane.gate);
    plane.points_below_gamma = c.read_double(s, "points_below_gamma", plane.points_below_gamma);
    MRPT_LOAD_CONFIG_VAR(voxel_nearest_above, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_fit_residual, double, c, s);
    MRPT_LOAD_CONFIG_VAR(point_weight, double, c, s);
}

void AssociationConfig::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    c.write(s, "kind", std::string(associationKindName(kind)), mrpt::config::MRPT_SAVE_NAME_PADDING(),
            mrpt::config::MRPT_SAVE_VALUE_PADDING(),
            "planes (voxel planes, else nearest map point in a bounded grid) | nearest (kd-tree) | voxel (voxel map)");
    const auto save = [&](const char* key, double v, const char* comment) {
        c.write(s, key, v, mrpt::config::MRPT_SAVE_NAME_PADDING(), mrpt::config::MRPT_SAVE_VALUE_PADDING(), comment);
    };
    c.write(s, "plane_min_points", plane.min_points, mrpt::config::MRPT_SAVE_NAME_PADDING(),
            mrpt::config::MRPT_SAVE_VALUE_PADDING(), "planes: map points in a voxel for its plane at least");
    save("plane_thickness", plane.thickness, "[m] planes: the voxel's RMS distance to its plane at most");
    save("plane_min_spread", plane.min_spread, "[m] planes: the voxel's RMS spread across the plane at least");
    save("plane_footprint", plane.footprint, "[-] planes: the feature within this many in-plane spreads of the centroid");
    save("plane_gate", plane.gate, "[m] planes: the feature this near the voxel's plane at most");
    save("points_below_gamma", plane.points_below_gamma,
         "[-] planes: a frame with a translation gamma below this takes no voxel plane (0: never)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(voxel_nearest_above, "[m] voxel: features in thicker finest voxels (or none) use the kd-tree (0: never)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_fit_residual, "[m] map plane fit RMS giving weight 0");
    MRPT_SAVE_CONFIG_VAR_COMMENT(point_weight, "[-] weight of point-to-point correspondences (0: none used)");
}

void AssociationConfig::validate() const {
    const auto positive = [](double v, const char* key) {
        if (!(v > 0) || !std::isfinite(v)) throw ConfigError(std::string("[association] ") + key + " must be > 0");
    };
    if (plane.min_points < 3) throw ConfigError("[association] plane_min_points must be >= 3");
    positive(plane.thickness, "plane_thickness");
    if (!(plane.min_spread >= 0) || !std::isfinite(plane.min_spread))
        throw ConfigError("[association] plane_min_spread must be >= 0");
    positive(plane.footprint, "plane_footprint");
    positive(plane.gate, "plane_gate");
    if (!(voxel_nearest_above >= 0) || !std::isfinite(voxel_nearest_above))
        throw ConfigError("[association] voxel_nearest_above must be >= 0");
    positive(max_fit_residual, "max_fit_residual");
    if (!(plane.points_below_gamma >= 0 && plane.points_below_gamma <= 1.0 + 1e-12))
        throw ConfigError("[association] points_below_gamma must be in [0, 1]");
    if (!(point_weight >= 0) || !std::isfinite(point_weight)) throw ConfigError("[association] point_weight must be >= 0");
}

}  // namespace superloc::localization
