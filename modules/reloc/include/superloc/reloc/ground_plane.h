// The scan's own gravity estimate: the ground plane under the sensor (RANSAC), when no IMU
// knows the LiDAR's roll and pitch. doc/relocalization.md §2.
#pragma once

#include <superloc/core/types.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace superloc::reloc {

struct GroundPlaneParams {
    double max_tilt_deg = 45;     ///< [deg] the plane's normal within this angle of the lidar's z axis
    double max_range = 20;        ///< [m] candidate points within this horizontal range
    double min_height = 0.2;      ///< [m] the sensor at least this far above the plane
    double max_height = 5.0;      ///< [m] and at most this far
    double inlier_dist = 0.1;     ///< [m] point-to-plane distance of an inlier
    int iterations = 200;         ///< RANSAC samples
    size_t min_inliers = 30;      ///< fewer inliers: no ground found
    uint32_t seed = 1;            ///< RANSAC random seed (deterministic)
};

/// The largest plane below the sensor whose normal is within `max_tilt_deg` of the lidar's z axis.
struct GroundPlane {
    bool found = false;
    Vec3d normal_lidar = Vec3d::UnitZ();  ///< unit, pointing up (away from the ground), lidar frame
    double height = 0;                    ///< [m] distance of the lidar origin above the plane
    size_t inliers = 0;                   ///< points within inlier_dist of the plane
    size_t candidates = 0;                ///< points the RANSAC drew from
    /// Roll/pitch only (zero ZYX yaw): maps lidar vectors into a gravity-aligned frame in which
    /// the plane's normal is +z.
    Mat3d R_level_lidar = Mat3d::Identity();
};

/// RANSAC plane fit with a least-squares refit on the inliers. Candidates are the points with
/// z < -min_height/2 (below the sensor in lidar axes) within `max_range` horizontally. When
/// `R_level_lidar` is given (an IMU knows the tilt) only the height is estimated: the points are
/// levelled first and the normal must be within 5 deg of vertical.
GroundPlane estimateGroundPlane(const std::vector<Vec3f>& points_lidar, const GroundPlaneParams& params,
                                const Mat3d* R_level_lidar = nullptr);

/// `R` with its ZYX yaw removed (Ry(pitch) Rx(roll)): Rz(yaw) * removeYaw(R) has ZYX yaw `yaw`.
Mat3d removeYaw(const Mat3d& R);
/// ZYX yaw of a rotation [rad], in (-pi, pi].
double yawOf(const Mat3d& R);

}  // namespace superloc::reloc
