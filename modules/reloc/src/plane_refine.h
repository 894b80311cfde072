// Short 6-DoF point-to-plane refinement of a hypothesis in the map's registration voxel map
// (coarse to fine), Gauss-Newton with a Cauchy kernel. Internal to reloc.
#pragma once

#include <superloc/core/types.h>
#include <superloc/map/voxel_map.h>

#include <vector>

namespace superloc::reloc {

struct RefineResult {
    SE3d T_map_lidar = SE3d::Identity();
    bool converged = false;  ///< the finest level settled
    double inliers = 0;      ///< [-] fraction of the points within inlier_dist of a plane (finest level)
    double rms = 0;          ///< [m] RMS residual of those inliers
    double inliers_start = 0;  ///< [-] the same fraction at the start pose
};

RefineResult refinePointToPlane(const map::VoxelMap& voxels, const std::vector<Vec3f>& points_lidar,
                                const SE3d& T0_map_lidar, int iterations, double inlier_dist);

}  // namespace superloc::reloc
