// Data association with the prior map at a pose (doc/localizer.md step 3; paper §III-A), three
// ways ([association] kind, doc/map.md):
//  - planes (default): the finest voxel containing the feature (one hash probe) when its plane
//    is validated (enough points, thinner than an absolute bound, the feature projecting inside
//    the points' footprint and near the plane); otherwise the nearest map point within max_dist
//    (PriorMap::grid, 125 cells at most) and that point's precomputed geometry,
//    as `nearest` uses it. No search is unbounded.
//  - nearest: the nearest map point (kd-tree, unbounded) and its precomputed neighbourhood
//    geometry decide a point-to-plane, -line or -point correspondence with a fit weight;
//  - voxel: the registration voxel map's voxel that contains the feature (one hash probe, at the
//    level asked for) and that voxel's point statistics decide it (doc/map.md); at the finest
//    level, a feature whose voxel is thicker than nearest_above_thickness (or missing) is
//    associated as by `nearest` (the hybrid of doc/map.md).
#pragma once

#include <superloc/features/features_params.h>
#include <superloc/fusion/scan_factor.h>
#include <superloc/localization/association_config.h>
#include <superloc/localization/localization_params.h>
#include <superloc/map/prior_map.h>

#include <vector>

namespace superloc::localization {

/// The defaults are the run's: trackingAssociation() of the default [association],
/// [localization] and [features] (doc/parameters.md).
struct AssociationParams {
    AssociationKind kind = AssociationKind::Planes;
    int level = 0;                     ///< voxel map level (0 = finest), voxel association only
    /// [m] voxel, finest level: a feature whose voxel is thicker than this, or that has none, is
    /// associated as `nearest` does (kd-tree); 0: never
    double nearest_above_thickness = 0;
    double max_dist = 1.0;             ///< [m] plane / line / centroid farther: no correspondence
    double plane_max_thickness = 0.5;  ///< see features::classifyShape ([features] plane_max_thickness)
    double line_min_linearity = 0.7;
    /// [m] plane fit RMS giving weight 0 at the finest level; a level of voxel edge s uses
    /// max(max_fit_residual, 0.1 s) (coarse voxels hold rougher patches)
    double max_fit_residual = 0.1;
    /// weight of a point-to-point (centroid) correspondence; 0: such a correspondence is counted
    /// (AssociationStats::point), not kept ([localization] point_weight)
    double point_weight = 0.0;
    size_t line_knn = 6;               ///< nearest: neighbours used for a line's direction
    PlaneRule plane;                   ///< planes: when a finest voxel's plane is used ([association])
    /// planes: false gives every feature the bounded fallback (its nearest map point's own
    /// geometry, as `nearest`), no voxel plane: what a frame the risk step finds weak in
    /// translation uses, where a voxel plane's smoothing would drop the little a surface's
    /// texture says along the weak axis (IcpRegistration, doc/map.md)
    bool voxel_planes = true;
    bool voxel() const { return kind == AssociationKind::Voxel; }
};

/// The run's association at the finest level from [association] (planes, nearest, voxel or the
/// hybrid), [localization] max_corr_dist and the [features] shape thresholds.
AssociationParams trackingAssociation(const AssociationConfig& ac, const LocalizationParams& lp,
                                      const features::FeaturesParams& fp);

struct AssociationStats {
    size_t plane = 0, line = 0, point = 0;  ///< correspondences by type
    size_t too_far = 0;                     ///< features with no map point / voxel within max_dist
    size_t voxel_planes = 0;                ///< planes: features given their voxel's plane (the rest fell back)
    size_t total() const { return plane + line + point; }
};

/// planes: what each feature's last fallback search found, so that a later round need not search
/// again where the answer cannot have changed. The search also bounds the second nearest map
/// point's distance (PointGrid::nearest's `second`): a feature that has moved by less than half
/// the gap between the two since has the same nearest point, so the same correspondence
/// (a line's, whose direction is fitted to the points around the feature itself, is always
/// searched again). The answers are exactly those without it. Valid for one map, one feature
/// vector (its address and size) and one max_dist; anything else starts it afresh.
/// IcpRegistration keeps one per solve.
struct AssociationMemo {
    std::vector<Vec3f> at;          ///< the map position of the feature's last search
    std::vector<float> keep2;       ///< [m^2] moved less than this far (squared): the same answer; < 0: search
    std::vector<uint32_t> nearest;  ///< the map point that search found
    double max_dist = -1;           ///< the association's max_dist when recorded (< 0: nothing recorded)
    const void* features = nullptr;  ///< the feature vector and the map it was recorded for
    const void* map = nullptr;
    size_t reused = 0;              ///< features answered from the memo in the last call
    bool validFor(const void* f, size_t n, const void* m, double d) const {
        return max_dist >= 0 && features == f && map == m && at.size() == n && max_dist == d;
    }
    /// Forgets every answer (a new solve), keeping the memory.
    void clear() { max_dist = -1; }
};

/// Appends (after clearing) one correspondence per associated feature to `out`; `feature_of`
/// (if not null) receives the feature index of each correspondence. pts_body are the features
/// in the body frame, T_map_body the pose to associate at. `nearest_hint` (planes, if not null):
/// per feature, a map point of this map (or map::PointGrid::kNone), e.g. the one the last round
/// found; the bounded search starts from its distance, so that only the cells nearer than it are
/// visited, and it receives the nearest point found. The answers are those without it.
/// `memo` (planes, if not null): each feature's fallback answered from it where it cannot have
/// changed, and every fallback search recorded in it (AssociationMemo; the same answers).
void associate(const std::vector<Vec3d>& pts_body, const SE3d& T_map_body,
               const map::PriorMap& map, const AssociationParams& p,
               std::vector<Correspondence>& out, AssociationStats& stats,
               std::vector<uint32_t>* feature_of = nullptr, std::vector<uint32_t>* nearest_hint = nullptr,
               AssociationMemo* memo = nullptr);

/// Fraction of features whose nearest-map-point residual (plane/line/point distance of their
/// correspondence) is below `inlier_dist` at T_map_body, and the RMS of those residuals.
struct InlierStats {
    double ratio = 0;
    double rms = 0;   ///< [m] over inliers
    size_t inliers = 0;
};
InlierStats inlierStats(const std::vector<Correspondence>& corr, size_t n_features,
                        const SE3d& T_map_body, double inlier_dist);

}  // namespace superloc::localization
