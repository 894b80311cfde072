// superloc-import: converts a folder of scans or a ROS 1 / ROS 2 bag into a rawlog; the work is
// io::importKitti / io::importPcdFolder / io::importRosbag.
#include <CLI/CLI.hpp>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/system/progress.h>
#include <superloc/app/command_line.h>
#include <superloc/app/import_app.h>
#include <superloc/app/ini_sections.h>
#include <superloc/core/config.h>
#include <superloc/io/importers.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/rosbag.h>
#include <superloc/io/tum.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace superloc::app {
namespace {

struct Args {
    std::string kitti, pcd_dir, rosbag, poses, times, out, config, imu_csv, odom_csv, gt_tum;
    std::vector<std::string> sets;
    bool quiet = false, help = false, list = false, dump_config = false;
};

void defineCommandLine(CLI::App& cli, Args& a) {
    cli.description("Converts a folder of scans or a ROS 1 / ROS 2 bag into a rawlog (doc/your-data.md).");
    auto* kitti = cli.add_option("--kitti", a.kitti, "KITTI odometry folder: DIR/velodyne/NNNNNN.bin and DIR/times.txt")
                      ->type_name("DIR");
    auto* pcd = cli.add_option("--pcd-dir", a.pcd_dir, "folder of PCD scans (sorted by file name)")->type_name("DIR");
    auto* bag = cli.add_option("--rosbag", a.rosbag,
                               "ROS 1 .bag, ROS 2 .db3 (SQLite) or .mcap (or a ROS 2 bag folder holding one of\n"
                               "them): sensor_msgs/PointCloud2 (per-point time kept), sensor_msgs/Imu,\n"
                               "nav_msgs/Odometry (odom_alt / gt), geometry_msgs/PoseStamped (gt), the LiDAR\n"
                               "extrinsic from /tf_static; topics in the [rosbag] INI section")
                    ->type_name("BAG");
    kitti->excludes(pcd)->excludes(bag);
    pcd->excludes(bag);
    cli.add_flag("--list", a.list, "with --rosbag: print the bag's topics, types and message counts")->needs(bag);
    cli.add_option("--config", a.config, "INI file with a [rosbag] section (doc/your-data.md)")->type_name("INI");
    app::addSetOption(cli, a.sets);
    cli.add_flag("--dump-config", a.dump_config, "print the effective [rosbag] section and exit");
    cli.add_option("--poses", a.poses,
                   "ground-truth poses (T_world_lidar), one per scan or matched by time; written as\n"
                   "`gt` CObservationRobotPose observations (--kitti, --pcd-dir)")
        ->type_name("TUM")
        ->excludes(bag);
    cli.add_option("--times", a.times,
                   "scan times [s], one per line (default: DIR/times.txt for KITTI, the --poses\n"
                   "timestamps for a PCD folder)")
        ->type_name("FILE")
        ->excludes(bag);
    cli.add_option("--imu-csv", a.imu_csv, "IMU samples to add: t, ax, ay, az, wx, wy, wz per line (header optional)")
        ->type_name("F");
    cli.add_option("--odom-csv", a.odom_csv,
                   "second odometry to add as `odom_alt`: t x y z qx qy qz qw [+ 21 values, the\n"
                   "covariance's upper triangle row by row, x y z roll pitch yaw]")
        ->type_name("F");
    cli.add_option("--gt-tum", a.gt_tum, "also write the rawlog's `gt` poses as a TUM file (for evo, superloc-eval)")
        ->type_name("F");
    cli.add_option("--out", a.out, "output rawlog (one LiDAR observation per scan, label `lidar`)")
        ->type_name("FILE.rawlog");
    cli.add_flag("--quiet", a.quiet, "no summary on stdout");
}

Args parse(const std::vector<std::string>& args) {
    Args a;
    CLI::App cli("", "superloc-import");
    defineCommandLine(cli, a);
    a.help = !app::parseCommandLine(cli, args);
    if (a.help || a.dump_config) return a;
    if (int(!a.kitti.empty()) + int(!a.pcd_dir.empty()) + int(!a.rosbag.empty()) != 1)
        throw std::runtime_error(
            "give exactly one of --kitti DIR, --pcd-dir DIR or --rosbag BAG (see --help)");
    if (a.out.empty() && !a.list) throw std::runtime_error("--out FILE.rawlog is required (see --help)");
    return a;
}

io::RosbagParams loadRosbagParams(const Args& a) {
    mrpt::config::CConfigFileMemory cfg;
    std::string source = "command line";
    if (!a.config.empty()) {
        source = a.config;
        loadIniFile(cfg, a.config);
    }
    for (const auto& s : a.sets) applyOverride(cfg, s);
    checkSections(cfg, importSections(), a.config, a.sets);
    return loadParams<io::RosbagParams>(
        cfg, "rosbag", a.sets.empty() ? source : source + " / --set");
}

/// One warning line for the scans left out because they had no valid point.
void warnEmptyScans(const io::ImportResult& r) {
    if (r.empty_scans > 0)
        std::cerr << "superloc-import: warning: " << r.empty_scans << " empty scan"
                  << (r.empty_scans > 1 ? "s" : "") << " (no valid point) not imported, the first: "
                  << r.first_empty << "\n";
}

/// --gt-tum: the `gt` poses of the written rawlog as TUM.
void writeGtTum(const Args& a, const std::string& gt_label) {
    if (a.gt_tum.empty()) return;
    io::RawlogParams rp;
    rp.gt_label = gt_label;
    rp.scan_period = 0;
    io::RawlogReader reader(a.out, rp);
    Trajectory gt;
    io::RawlogItem it;
    while (reader.next(it))
        if (it.kind == io::RawlogItem::Kind::GroundTruth) gt.push_back(it.pose());
    if (gt.empty()) throw std::runtime_error("--gt-tum: " + a.out + " has no `" + gt_label + "` poses");
    io::saveTum(a.gt_tum, gt);
}

int runRosbag(const Args& a, const io::RosbagParams& params,
              const io::ProgressFn& bar, io::ImportExtras extras) {
    if (a.list) {
        for (const auto& t : io::listRosbag(a.rosbag))
            std::cout << t.topic << "  " << t.type << "  " << t.messages << " messages\n";
        return 0;
    }
    extras.imu_label = params.imu_label;
    extras.odom_alt_label = params.odom_alt_label;
    const auto r = io::importRosbag(a.rosbag, params, a.out, bar, extras);
    for (const auto& s : r.stamps)
        if (!s.reason.empty())
            std::cerr << "superloc-import: notice: " << a.rosbag << ": topic '" << s.topic
                      << "': " << s.reason << ": stamped with the bag's record time instead "
                      << "([rosbag] stamp_source = auto; header keeps header.stamp)\n";
    for (const auto& [topic, n] : r.non_monotonic) {
        bool record = false;
        for (const auto& s : r.stamps) record = record || (s.topic == topic && s.record_time);
        std::cerr << "superloc-import: warning: " << a.rosbag << ": topic '" << topic << "': " << n
                  << " messages skipped (" << (record ? "record time" : "header.stamp")
                  << " did not increase)\n";
    }
    if (!a.quiet)
        std::cout << a.out << ": " << r.scans << " scans (" << r.lidar_topic << ", "
                  << r.timed_scans << " with per-point time"
                  << (r.time_field.empty() ? "" : " '" + r.time_field + "'") << "), " << r.points
                  << " points, " << r.imu << " imu, " << r.odom_alt << " odom_alt, " << r.gt_poses
                  << " gt poses, " << r.dropped_points << " NaN/inf points dropped\n";
    warnEmptyScans(r);
    writeGtTum(a, params.gt_label);
    return 0;
}

}  // namespace

std::string ImportApp::usage() {
    CLI::App cli("", "superloc-import");
    Args a;
    defineCommandLine(cli, a);
    return helpText(cli);
}

int ImportApp::run(const std::vector<std::string>& args) {
    const Args a = parse(args);
    if (a.help) {
        std::cout << usage();
        return 0;
    }
    const auto rosbag_params = loadRosbagParams(a);
    if (a.dump_config) {
        mrpt::config::CConfigFileMemory c;
        rosbag_params.saveToConfigFile(c, "rosbag");
        std::cout << c.getContent();
        return 0;
    }
    io::ProgressFn bar;
    if (isatty(STDERR_FILENO))
        bar = [](size_t done, size_t total) {
            std::fprintf(stderr, "\r%s %zu/%zu scans",
                         mrpt::system::progress(double(done) / total, 40).c_str(), done, total);
            if (done == total) std::fprintf(stderr, "\n");
        };
    io::ImportExtras extras;
    if (!a.imu_csv.empty()) extras.imu = io::loadImuCsv(a.imu_csv);
    if (!a.odom_csv.empty()) extras.odom_alt = io::loadOdomCsv(a.odom_csv);
    if (!a.rosbag.empty()) return runRosbag(a, rosbag_params, bar, extras);
    const auto r =
        a.kitti.empty()
            ? io::importPcdFolder(a.pcd_dir, a.poses, a.times, a.out, bar, extras)
            : io::importKitti(a.kitti, a.poses, a.times, a.out, bar, extras);
    if (!a.quiet)
        std::cout << a.out << ": " << r.scans << " scans, " << r.points << " points, " << r.gt_poses
                  << " gt poses, " << r.imu << " imu, " << r.odom_alt << " odom_alt, "
                  << r.dropped_points << " NaN/inf points dropped\n";
    warnEmptyScans(r);
    writeGtTum(a, "gt");
    return 0;
}

}  // namespace superloc::app
