// The superloc-map application (doc/io.md): command line -> map::MapBuilder -> map file (+ stats).
// apps/superloc-map/main.cpp only wraps this class and prints.
#pragma once

#include <superloc/map/map_builder.h>
#include <superloc/map/map_stats.h>

#include <exception>
#include <optional>
#include <string>
#include <vector>

namespace superloc::app {

struct MapAppArgs {
    map::MapBuildOptions build;
    std::string from_map;     ///< input map file instead of a rawlog/simplemap (--from-map)
    double tile_size = 0;     ///< [m] > 0: `out` is a tile directory (io/map_tiles.h)
    std::string out;          ///< output map (.pcd binary, .ply, .bin, .txt by extension)
    std::string config;       ///< optional INI ([rawlog] labels)
    std::vector<std::string> overrides;  ///< --set section.key=value
    bool stats = false;       ///< also compute normals and report the fit residuals
    bool help = false;
};


/// Parses the arguments (without the program name); throws ConfigError or std::runtime_error
/// with a one-line message on a bad command line.
MapAppArgs parseMapAppArgs(const std::vector<std::string>& args);
std::string mapAppUsage();

class MapApp {
   public:
    explicit MapApp(const MapAppArgs& args);
    /// Builds and writes the map; computes stats when asked.
    void run(const io::ProgressFn& progress = {});
    const map::MapBuildResult& result() const { return result_; }
    const std::optional<map::MapStats>& stats() const { return stats_; }
    /// The tiles written (--tile-size), else empty.
    size_t tilesWritten() const { return tiles_written_; }

   private:
    MapAppArgs args_;
    map::MapBuildResult result_;
    std::optional<map::MapStats> stats_;
    size_t tiles_written_ = 0;
};

}  // namespace superloc::app
