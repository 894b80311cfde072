// Section [association] of the INI: which association the localizer uses and its thresholds
// (association.h, doc/map.md "The planes association").
#pragma once

#include <superloc/core/types.h>
#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace superloc::localization {

/// planes: validated voxel planes, else the nearest map point within a bounded grid search (the
/// default); nearest: the nearest map point (kd-tree); voxel: the voxel map, coarse to fine.
enum class AssociationKind { Planes, Nearest, Voxel };
AssociationKind associationKindFromString(const std::string& s);  ///< throws ConfigError naming the key
const char* associationKindName(AssociationKind k);

/// planes: when a feature takes its finest (reg_voxel) voxel's plane ([association] plane_*). One
/// struct for the section and for the association that uses it (AssociationParams::plane).
struct PlaneRule {
    int min_points = 8;        ///< map points in the voxel at least
    /// [m] the voxel's points' RMS distance to their plane (sqrt of the smallest covariance
    /// eigenvalue) at most: an absolute bound, so a riser and a tread in one voxel fall back,
    /// and so does a rough cave wall (doc/map.md)
    double thickness = 0.015;
    double min_spread = 0.05;  ///< [m] their RMS spread across the plane at least (not a line)
    /// [-] the feature projected on the plane within this many RMS spreads of the centroid along
    /// each in-plane axis (inside the points' footprint; 1.73 spans a uniform patch)
    double footprint = 2.0;
    double gate = 0.25;        ///< [m] the feature this near the voxel's plane at most
    /// [-] a frame whose first round finds a translation axis's gamma below this takes no voxel
    /// plane at all (every feature on the bounded fallback, nearest's answer): a weak axis is held
    /// by the surfaces' texture, which voxel planes smooth away ([association]
    /// points_below_gamma, doc/map.md)
    double points_below_gamma = 0.5;
    /// Whether a frame of risk gammas `gamma` (x y z roll pitch yaw) is weak enough in
    /// translation to take no voxel plane.
    bool wantsPointGeometry(const Vec6d& gamma) const { return gamma.head<3>().minCoeff() < points_below_gamma; }
};

struct AssociationConfig : public mrpt::config::CLoadableOptions {
    /// planes | nearest | voxel (INI: its name; an unknown one is a ConfigError at load)
    AssociationKind kind = AssociationKind::Planes;
    /// planes: a feature takes its finest voxel's plane when this rule holds, else the nearest map
    /// point within max_corr_dist and that point's neighbourhood geometry (INI keys plane_*).
    PlaneRule plane;
    /// [m] voxel: a feature whose finest-level voxel is thicker than this (a step, an edge, a
    /// corner: a plane that smears the surface), or that has no finest-level voxel, is
    /// associated with its nearest map point instead (kd-tree, as `nearest`); 0: never
    double voxel_nearest_above = 0.0;
    double max_fit_residual = 0.1;   ///< [m] map plane fit RMS giving weight 0
    /// [-] weight of point-to-point correspondences (nearest map point: biased by the map voxel
    /// and slow to converge from a far initial pose, so off by default)
    double point_weight = 0.0;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    /// Throws ConfigError naming [association] and the key when a value is out of range.
    void validate() const;
};

}  // namespace superloc::localization
