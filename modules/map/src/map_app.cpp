// superloc-map: argument parsing, build, save, optional statistics.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <superloc/core/config.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/core/cli.h>
#include <superloc/map/map_app.h>
#include <superloc/map/prior_map.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace superloc::map {

namespace {

double parseNumber(const std::string& flag, const std::string& v) {
    double d;
    if (!parseDouble(v, d)) throw std::runtime_error(flag + ": '" + v + "' is not a number");
    return d;
}

double median(std::vector<float> v) {
    if (v.empty()) return std::nan("");
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

}  // namespace

std::string mapAppUsage() {
    return "Usage: superloc-map (--rawlog FILE [--poses TUM] | --simplemap FILE) [--voxel M]\n"
           "                    --out MAP.pcd [--min-range M] [--max-range M] [--body-poses]\n"
           "                    [--no-normals] [--stats] [--config INI]\n"
           "                    [--set rawlog.key=value]...\n"
           "Builds a prior map from a rawlog's LiDAR scans placed at their poses, or from an MRPT\n"
           "simplemap's keyframes.\n"
           "  --rawlog FILE   input rawlog (CObservationPointCloud/Velodyne/RotatingScan scans)\n"
           "  --simplemap F   input MRPT .simplemap (CSimpleMap): every point-cloud-like\n"
           "                  observation at its keyframe pose (PDF mean) and sensorPose\n"
           "  --poses TUM     scan poses T_map_lidar (t x y z qx qy qz qw), interpolated at each\n"
           "                  scan's time; default: the rawlog's `gt` CObservationRobotPose\n"
           "  --voxel M       output voxel size [m], each voxel keeps its centroid (default 0.1;\n"
           "                  0 keeps every point)\n"
           "  --out FILE      output map: .pcd (binary), .ply, .bin (KITTI), .txt or .pointsmap\n"
           "                  (a serialized MRPT CPointsMapXYZI)\n"
           "  --min-range M   drop scan points closer than M to the sensor (default 0.5)\n"
           "  --max-range M   drop scan points farther than M (default 0: no limit)\n"
           "  --body-poses    the poses are T_map_imu: apply each scan's sensorPose too\n"
           "  --no-normals    do not store per-point normals (by default they are written,\n"
           "                  flipped toward the side the scans saw each surface from)\n"
           "  --stats         compute per-point normals and print the median point-to-plane\n"
           "                  fit residual of the map (how sharp its surfaces are)\n"
           "  --config INI    INI file whose [rawlog] section sets the observation labels\n"
           "  --set S.K=V     override one INI key, e.g. --set rawlog.gt_label=groundtruth\n"
           "  --help          this text\n";
}

MapAppArgs parseMapAppArgs(int argc, const char* const* argv) {
    MapAppArgs a;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        const auto value = [&] { return flagValue(argc, argv, i); };
        if (flag == "--help" || flag == "-h") a.help = true;
        else if (flag == "--rawlog") a.build.rawlog = value();
        else if (flag == "--simplemap") a.build.simplemap = value();
        else if (flag == "--poses") a.build.poses_tum = value();
        else if (flag == "--voxel") a.build.voxel = parseNumber(flag, value());
        else if (flag == "--out") a.out = value();
        else if (flag == "--min-range") a.build.min_range = parseNumber(flag, value());
        else if (flag == "--max-range") a.build.max_range = parseNumber(flag, value());
        else if (flag == "--body-poses") a.build.body_poses = true;
        else if (flag == "--no-normals") a.build.normals = false;
        else if (flag == "--stats") a.stats = true;
        else if (flag == "--config") a.config = value();
        else if (flag == "--set") a.overrides.push_back(value());
        else throw std::runtime_error("unknown argument '" + flag + "' (see --help)");
    }
    if (a.help) return a;
    if (a.build.rawlog.empty() == a.build.simplemap.empty())
        throw std::runtime_error("give one of --rawlog FILE or --simplemap FILE (see --help)");
    if (!a.build.simplemap.empty() && !a.build.poses_tum.empty())
        throw std::runtime_error("--poses goes with --rawlog; a simplemap holds its own poses");
    if (a.out.empty()) throw std::runtime_error("missing --out MAP.pcd (see --help)");
    if (io::formatFromExtension(a.out) == io::CloudFormat::MrptSimpleMap)
        throw std::runtime_error(a.out + ": cannot write a .simplemap; use .pointsmap");
    if (!a.build.rawlog.empty() && !std::filesystem::exists(a.build.rawlog))
        throw std::runtime_error(a.build.rawlog + ": no such rawlog");
    if (!a.build.simplemap.empty() && !std::filesystem::exists(a.build.simplemap))
        throw std::runtime_error(a.build.simplemap + ": no such simplemap");

    mrpt::config::CConfigFileMemory cfg;
    std::string source = "--set";
    if (!a.config.empty()) {
        if (!std::filesystem::exists(a.config))
            throw std::runtime_error(a.config + ": no such INI file");
        std::ifstream in(a.config);
        std::stringstream text;
        text << in.rdbuf();
        setIniContent(cfg, text.str(), a.config);
        source = a.config;
    }
    for (const auto& o : a.overrides) applyOverride(cfg, o);
    a.build.rawlog_params = loadParams<io::RawlogParams>(cfg, "rawlog", source);
    return a;
}

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

MapApp::MapApp(const MapAppArgs& args) : args_(args) {}

void MapApp::run(const io::ProgressFn& progress) {
    MapBuilder builder(args_.build);
    const PointCloud map = builder.build(progress);
    result_ = builder.result();
    io::savePointCloud(args_.out, map);
    if (args_.stats) {
        MapParams p;
        p.normal_max_radius = std::max(0.5, 5 * args_.build.voxel);
        stats_ = computeMapStats(map, p);
    }
}

}  // namespace superloc::map
