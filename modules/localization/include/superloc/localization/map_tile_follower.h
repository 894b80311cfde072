// A tiled prior map (map::TiledMap) that follows the robot (doc/map.md "Tiled maps"): the tiles
// around the start are loaded at once; later, half-way to `[map] tile_reload` from the centre in
// use, the tiles around the robot are read and prepared in a thread (Localizer::prepareMap), and
// at `tile_reload` they are swapped into the Localizer between two frames, waiting only if they
// are not ready yet. Both points depend on the poses alone, so a run is reproducible. Used by
// LocalizeApp; a ROS node would call it the same way after each frame.
#pragma once

#include <superloc/localization/localizer.h>
#include <superloc/map/tiled_map.h>

#include <future>
#include <memory>
#include <string>

namespace superloc::localization {

class MapTileFollower {
   public:
    struct Stats {
        size_t reloads = 0;      ///< maps swapped in after the first
        size_t points_max = 0;   ///< largest map loaded
        double load_s_max = 0;   ///< longest tile read + PriorMap preparation (in the thread)
        double wait_s_max = 0;   ///< longest wait of the caller for a map to be ready and swapped in
    };

    /// Reads the tile index of `dir` (throws like io::readMapTileIndex); `map` gives the load
    /// filter and tile_radius / tile_reload, `params` what prepareMap builds.
    MapTileFollower(const std::string& dir, const map::MapParams& map, const LocalizerParams& params);
    /// Waits for a load in flight.
    ~MapTileFollower();

    /// The tiles within tile_radius of `p`, for the Localizer's construction; empty when none.
    std::shared_ptr<const map::PriorMap> start(const Vec3d& p);
    /// After a frame whose pose is at `p`: starts loading the tiles around it, or swaps them into
    /// `loc`. Returns true when a map was swapped in. Rethrows a load's error (a corrupt tile).
    bool update(const Vec3d& p, Localizer& loc);

    const Stats& stats() const { return stats_; }
    const map::TiledMap& tiles() const { return tiles_; }

   private:
    map::TiledMap tiles_;
    map::MapParams map_params_;
    LocalizerParams params_;
    Vec3d center_ = Vec3d::Zero();  ///< centre of the tiles in use (tiles_.center(): of the last load)
    std::future<PreparedMap> next_;
    Stats stats_;
};

}  // namespace superloc::localization
