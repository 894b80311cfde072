#include <superloc/map/map_stats.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace superloc::map {
namespace {

double median(std::vector<float> v) {
    if (v.empty()) return std::nan("");
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

}  // namespace

MapStats computeMapStats(const PointCloud& map, const MapParams& params) {
    MapParams p = params;
    p.voxel_size = 0;  // the map is already voxelized: judge it as written
    const PriorMap pm(map, p);
    MapStats s;
    s.points = pm.size();
    s.prepare_seconds = pm.prepareSeconds();
    std::vector<float> all, planar;
    for (size_t i = 0; i < pm.size(); ++i) {
        const auto& g = pm.geometry(i);
        if (!std::isfinite(g.fit_residual)) continue;
        all.push_back(g.fit_residual);
        if (g.planarity > 0.5f) planar.push_back(g.fit_residual);
    }
    s.with_geometry = all.size();
    s.median_fit_residual = median(all);
    s.median_planar_fit_residual = median(planar);
    s.planar_fraction = all.empty() ? 0.0 : static_cast<double>(planar.size()) / all.size();
    return s;
}

}  // namespace superloc::map
