// Map accuracy (paper Table I, doc/evaluation.md): the localized map against the ground-truth map.
#pragma once

#include <superloc/core/types.h>

#include <cstddef>

namespace superloc::eval {

struct MapResult {
    size_t points = 0;  ///< localized-map points after the voxel filter
    size_t gt_points = 0;
    double outlier_percent = 0;  ///< [%] points farther than the threshold from the GT map
    double median_dist = 0;      ///< [m] median nearest-neighbour distance to the GT map
    double mean_dist = 0;        ///< [m]
    double threshold = 0;        ///< [m] the outlier threshold used
};

/// Voxelizes `est_map` at `voxel` [m] (0 = keep all), then for each point finds the nearest
/// GT map point (kd-tree); outlier when the distance is > `threshold` [m]. Throws
/// std::invalid_argument when either map is empty.
MapResult computeMapOutliers(const PointCloud& est_map, const PointCloud& gt_map, double voxel,
                             double threshold);

}  // namespace superloc::eval
