// TiledMap: the tiles within a radius of a point, read and prepared as one PriorMap.
#include <mrpt/system/CTicTac.h>
#include <superloc/core/config.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/map/tiled_map.h>

#include <algorithm>
#include <cmath>

namespace superloc::map {

TiledMap::TiledMap(const std::string& dir, const MapParams& params, double radius)
    : index_(io::readMapTileIndex(dir)), params_(params), radius_(radius) {
    params_.validate();
    if (!std::isfinite(radius) || radius <= 0) throw ConfigError("TiledMap: the radius must be > 0 m");
}

std::shared_ptr<const PriorMap> TiledMap::loadAround(const Vec3d& center) {
    mrpt::system::CTicTac timer;
    const double s = index_.tile_size;
    PointCloud all;
    bool normals = true, intensity = true;
    tiles_loaded_ = 0;
    for (const io::MapTile& t : index_.tiles) {
        // Distance in x-y from the centre to the tile's square.
        const double x0 = static_cast<double>(t.ix) * s, y0 = static_cast<double>(t.iy) * s;
        const double dx = std::max({x0 - center.x(), 0.0, center.x() - (x0 + s)});
        const double dy = std::max({y0 - center.y(), 0.0, center.y() - (y0 + s)});
        if (dx * dx + dy * dy > radius_ * radius_) continue;
        PointCloud c = io::loadPointCloud(t.file);
        normals = normals && c.normals.size() == c.size();
        intensity = intensity && c.intensity.size() == c.size();
        all.points.insert(all.points.end(), c.points.begin(), c.points.end());
        all.normals.insert(all.normals.end(), c.normals.begin(), c.normals.end());
        all.intensity.insert(all.intensity.end(), c.intensity.begin(), c.intensity.end());
        ++tiles_loaded_;
    }
    if (!normals) all.normals.clear();
    if (!intensity) all.intensity.clear();
    points_loaded_ = all.size();
    center_ = center;
    auto map = std::make_shared<const PriorMap>(all, params_);
    last_seconds_ = timer.Tac();
    return map;
}

}  // namespace superloc::map
