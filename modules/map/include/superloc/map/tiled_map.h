// A prior map too large for memory, localized in through the tiles around the robot
// (io/map_tiles.h for the files, doc/map.md "Tiled maps").
//
// loadAround() reads the tiles whose square comes within `radius` of a point (in x-y) and
// prepares them as one PriorMap; the caller (LocalizeApp) swaps it into the Localizer between
// frames when the robot has moved `reload_distance` from the last centre. Memory and preparation
// then depend on the radius, not on the map's extent.
#pragma once

#include <superloc/io/map_tiles.h>
#include <superloc/map/prior_map.h>

#include <memory>
#include <string>

namespace superloc::map {

class TiledMap {
   public:
    /// Reads the tile index of `dir` (throws like io::readMapTileIndex); radius > 0 [m].
    TiledMap(const std::string& dir, const MapParams& params, double radius);

    /// A PriorMap of the tiles within `radius` of `center` (x-y); empty when there are none.
    /// Remembers `center` and the tiles loaded.
    std::shared_ptr<const PriorMap> loadAround(const Vec3d& center);

    const io::MapTileIndex& index() const { return index_; }
    double radius() const { return radius_; }
    /// Centre of the last loadAround, and the number of tiles and points it loaded.
    const Vec3d& center() const { return center_; }
    size_t tilesLoaded() const { return tiles_loaded_; }
    size_t pointsLoaded() const { return points_loaded_; }
    /// Seconds the last loadAround spent reading the tiles and preparing the PriorMap.
    double lastLoadSeconds() const { return last_seconds_; }

   private:
    io::MapTileIndex index_;
    MapParams params_;
    double radius_;
    Vec3d center_ = Vec3d::Zero();
    size_t tiles_loaded_ = 0, points_loaded_ = 0;
    double last_seconds_ = 0;
};

}  // namespace superloc::map
