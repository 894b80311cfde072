// How sharp a map's surfaces are (superloc-map --stats): per-point PCA fit residuals summarised.
#pragma once

#include <superloc/core/types.h>
#include <superloc/map/prior_map.h>

#include <cstddef>

namespace superloc::map {

/// Quality of a map's surfaces: per-point PCA (MapParams normal_k/normal_max_radius, no voxel
/// filter) summarised. "Sharp walls" = small median point-to-plane fit residual.
struct MapStats {
    size_t points = 0;
    size_t with_geometry = 0;          ///< points with >= 3 neighbours in the radius
    double median_fit_residual = 0;    ///< [m] median RMS point-to-plane distance of neighbourhoods
    double median_planar_fit_residual = 0;  ///< [m] the same over planar points (planarity > 0.5)
    double planar_fraction = 0;        ///< share of points with planarity > 0.5
    double prepare_seconds = 0;        ///< PriorMap preparation time
};
MapStats computeMapStats(const PointCloud& map, const MapParams& params);

}  // namespace superloc::map
