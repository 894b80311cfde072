// A prior map split in square tiles on disk, so that a map larger than memory can be localized
// in by loading the tiles around the robot (map::TiledMap, doc/map.md "Tiled maps").
//
// A tile directory holds `tiles.csv` and one binary PCD per non-empty tile. Tile (ix, iy) holds
// the points with floor(x / tile_size) = ix and floor(y / tile_size) = iy (z is not split), with
// their normals, intensity and colours when the map has them:
//
//   # superloc map tiles: tile (ix, iy) holds the points with floor(x/s) = ix, floor(y/s) = iy
//   tile_size,50
//   ix,iy,points,file
//   0,0,123456,tile_0_0.pcd
#pragma once

#include <superloc/core/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace superloc::io {

struct MapTile {
    int64_t ix = 0, iy = 0;
    size_t points = 0;
    std::string file;  ///< path of the tile's PCD (directory + the index's file name)
};

struct MapTileIndex {
    std::string dir;
    double tile_size = 0;  ///< [m] edge of the square tiles
    std::vector<MapTile> tiles;
    size_t totalPoints() const;
};

/// Splits `cloud` into tiles of `tile_size` metres and writes them and tiles.csv into `dir`
/// (created; existing tile files there are overwritten). Throws std::runtime_error naming the
/// directory or file on failure, std::invalid_argument for tile_size <= 0 or not finite.
MapTileIndex writeMapTiles(const PointCloud& cloud, double tile_size, const std::string& dir);

/// Reads `dir`/tiles.csv. Throws std::runtime_error with a one-line message naming the file
/// and line for a missing or malformed index, or a tile file that does not exist.
MapTileIndex readMapTileIndex(const std::string& dir);

/// True when `path` is a directory holding a tiles.csv.
bool isMapTileDir(const std::string& path);

}  // namespace superloc::io
