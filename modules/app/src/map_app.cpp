#include <CLI/CLI.hpp>
// superloc-map: argument parsing, build, save, optional statistics.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <superloc/core/config.h>
#include <superloc/io/map_tiles.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/app/command_line.h>
#include <superloc/app/ini_sections.h>
#include <superloc/app/map_app.h>
#include <superloc/map/prior_map.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace superloc::app {

namespace {

void defineCommandLine(CLI::App& cli, MapAppArgs& a) {
    cli.description(
        "Builds a prior map from a rawlog's LiDAR scans placed at their poses, or from an MRPT\n"
        "simplemap's keyframes.");
    auto* rawlog = cli.add_option("--rawlog", a.build.rawlog,
                                  "input rawlog (CObservationPointCloud/Velodyne/RotatingScan scans)")
                       ->type_name("FILE");
    cli.add_option("--simplemap", a.build.simplemap,
                   "input MRPT .simplemap (CSimpleMap): every point-cloud-like observation at its\n"
                   "keyframe pose (PDF mean) and sensorPose")
        ->type_name("FILE")
        ->excludes(rawlog);
    cli.add_option("--from-map", a.from_map,
                   "input map file (any format --out writes, or .simplemap/.pointsmap) written as it is:\n"
                   "to convert a map or split it into tiles (--tile-size)")
        ->type_name("FILE")
        ->excludes(rawlog);
    cli.add_option("--tile-size", a.tile_size,
                   "split the map into square x-y tiles of M metres: --out is then a directory of\n"
                   "tile_IX_IY.pcd files and tiles.csv, for superloc-localize --map DIR (doc/map.md)")
        ->type_name("M");
    cli.add_option("--poses", a.build.poses_tum,
                   "scan poses T_map_lidar (t x y z qx qy qz qw), interpolated at each scan's time;\n"
                   "default: the rawlog's `gt` CObservationRobotPose")
        ->type_name("TUM")
        ->needs(rawlog);
    cli.add_option("--voxel", a.build.voxel, "output voxel size [m], each voxel keeps its centroid (0 keeps every point)")
        ->type_name("M")
        ->capture_default_str();
    cli.add_option("--out", a.out, "output map: .pcd (binary), .ply, .bin (KITTI), .txt or .pointsmap\n"
                                   "(a serialized MRPT CPointsMapXYZI)")
        ->type_name("MAP.pcd")
        ->required();
    cli.add_option("--min-range", a.build.min_range, "drop scan points closer than M to the sensor")
        ->type_name("M")
        ->capture_default_str();
    cli.add_option("--max-range", a.build.max_range, "drop scan points farther than M (0: no limit)")
        ->type_name("M")
        ->capture_default_str();
    cli.add_flag("--body-poses", a.build.body_poses, "the poses are T_map_imu: apply each scan's sensorPose too");
    cli.add_flag("--no-normals{false}", a.build.normals,
                 "do not store per-point normals (by default they are written, flipped toward the\n"
                 "side the scans saw each surface from)");
    cli.add_flag("--stats", a.stats,
                 "compute per-point normals and print the median point-to-plane fit residual of the map");
    cli.add_option("--config", a.config, "INI file whose [rawlog] section sets the observation labels")
        ->type_name("INI");
    addSetOption(cli, a.overrides);
}

}  // namespace

std::string mapAppUsage() {
    CLI::App cli("", "superloc-map");
    MapAppArgs a;
    defineCommandLine(cli, a);
    return helpText(cli);
}

MapAppArgs parseMapAppArgs(const std::vector<std::string>& args) {
    MapAppArgs a;
    CLI::App cli("", "superloc-map");
    defineCommandLine(cli, a);
    a.help = !parseCommandLine(cli, args);
    if (a.help) return a;
    const int sources = !a.build.rawlog.empty() + !a.build.simplemap.empty() + !a.from_map.empty();
    if (sources != 1)
        throw std::runtime_error("give one of --rawlog FILE, --simplemap FILE or --from-map FILE (see --help)");
    if (!a.from_map.empty() && !std::filesystem::exists(a.from_map))
        throw std::runtime_error(a.from_map + ": no such map file");
    if (!(a.tile_size >= 0) || !std::isfinite(a.tile_size))
        throw std::runtime_error("--tile-size must be > 0 m");
    if (a.tile_size > 0) {
        if (std::filesystem::exists(a.out) && !std::filesystem::is_directory(a.out))
            throw std::runtime_error(a.out + ": --tile-size writes a directory, and this is a file");
    } else if (io::formatFromExtension(a.out) == io::CloudFormat::MrptSimpleMap) {
        throw std::runtime_error(a.out + ": cannot write a .simplemap; use .pointsmap");
    }
    if (!a.build.rawlog.empty() && !std::filesystem::exists(a.build.rawlog))
        throw std::runtime_error(a.build.rawlog + ": no such rawlog");
    if (!a.build.simplemap.empty() && !std::filesystem::exists(a.build.simplemap))
        throw std::runtime_error(a.build.simplemap + ": no such simplemap");

    mrpt::config::CConfigFileMemory cfg;
    std::string source = "--set";
    if (!a.config.empty()) {
        loadIniFile(cfg, a.config);
        source = a.config;
    }
    for (const auto& o : a.overrides) applyOverride(cfg, o);
    checkSections(cfg, mapSections(), a.config, a.overrides);
    a.build.rawlog_params = loadParams<io::RawlogParams>(cfg, "rawlog", source);
    return a;
}

MapApp::MapApp(const MapAppArgs& args) : args_(args) {}

void MapApp::run(const io::ProgressFn& progress) {
    PointCloud map;
    if (!args_.from_map.empty()) {
        map = io::loadPointCloud(args_.from_map);
        result_ = {};
        result_.points_in = result_.map_points = map.size();
    } else {
        map::MapBuilder builder(args_.build);
        map = builder.build(progress);
        result_ = builder.result();
    }
    if (args_.tile_size > 0)
        tiles_written_ = io::writeMapTiles(map, args_.tile_size, args_.out).tiles.size();
    else
        io::savePointCloud(args_.out, map);
    if (args_.stats) {
        map::MapParams p;
        p.normal_max_radius = std::max(0.5, 5 * args_.build.voxel);
        stats_ = map::computeMapStats(map, p);
    }
}

}  // namespace superloc::app
