// The superloc-map application (DESIGN §9): command line -> MapBuilder -> map file (+ stats).
// apps/superloc-map/main.cpp only wraps this class and prints.
#pragma once

#include <superloc/map/map_builder.h>

#include <exception>
#include <optional>
#include <string>
#include <vector>

namespace superloc::map {

struct MapAppArgs {
    MapBuildOptions build;
    std::string out;          ///< output map (.pcd binary, .ply, .bin, .txt by extension)
    std::string config;       ///< optional INI ([rawlog] labels)
    std::vector<std::string> overrides;  ///< --set section.key=value
    bool stats = false;       ///< also compute normals and report the fit residuals
    bool help = false;
};


/// Parses argv; throws std::runtime_error with a one-line message on a bad command line.
MapAppArgs parseMapAppArgs(int argc, const char* const* argv);
std::string mapAppUsage();

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
MapStats computeMapStats(const PointCloud& map, const struct MapParams& params);

class MapApp {
   public:
    explicit MapApp(const MapAppArgs& args);
    /// Builds and writes the map; computes stats when asked.
    void run(const io::ProgressFn& progress = {});
    const MapBuildResult& result() const { return result_; }
    const std::optional<MapStats>& stats() const { return stats_; }

   private:
    MapAppArgs args_;
    MapBuildResult result_;
    std::optional<MapStats> stats_;
};

}  // namespace superloc::map
