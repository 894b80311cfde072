// superloc-import (--kitti DIR | --pcd-dir DIR | --rosbag FILE.bag|.db3|.mcap [--list])
//                 [--poses TUM] [--times FILE] [--imu-csv F] [--odom-csv F] [--config INI]
//                 [--set S.K=V]... --out FILE.rawlog
// Converts a folder of scans or a ROS 1 / ROS 2 bag into a rawlog (DESIGN §9); the work is
// io::importKitti / io::importPcdFolder / io::importRosbag.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/system/progress.h>
#include <superloc/core/cli.h>
#include <superloc/core/config.h>
#include <superloc/core/errors.h>
#include <superloc/io/importers.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/rosbag.h>
#include <superloc/io/tum.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

const char* kUsage =
    "Usage: superloc-import (--kitti DIR | --pcd-dir DIR | --rosbag BAG [--list])\n"
    "                       [--poses TUM] [--times FILE] [--imu-csv F] [--odom-csv F]\n"
    "                       [--config INI] [--set rosbag.KEY=V]...\n"
    "                       --out FILE.rawlog\n"
    "  --kitti DIR    KITTI odometry folder: DIR/velodyne/NNNNNN.bin and DIR/times.txt\n"
    "  --pcd-dir DIR  folder of PCD scans (sorted by file name)\n"
    "  --rosbag BAG   ROS 1 .bag, ROS 2 .db3 (SQLite) or .mcap (or a ROS 2 bag folder holding\n"
    "                 one of them): sensor_msgs/PointCloud2 (per-point time kept),\n"
    "                 sensor_msgs/Imu, nav_msgs/Odometry (odom_alt / gt),\n"
    "                 geometry_msgs/PoseStamped (gt), the LiDAR extrinsic from /tf_static;\n"
    "                 topics in the [rosbag] INI section\n"
    "  --list         with --rosbag: print the bag's topics, types and message counts\n"
    "  --config INI   INI file with a [rosbag] section (doc/your-data.md)\n"
    "  --set S.K=V    override one INI key, e.g. --set rosbag.gt_topic=/ground_truth\n"
    "  --dump-config  print the effective [rosbag] section and exit\n"
    "  --poses TUM    ground-truth poses (T_world_lidar), one per scan or matched by time;\n"
    "                 written as `gt` CObservationRobotPose observations (--kitti, --pcd-dir)\n"
    "  --times FILE   scan times [s], one per line (default: DIR/times.txt for KITTI, the\n"
    "                 --poses timestamps for a PCD folder)\n"
    "  --imu-csv F    IMU samples to add: t, ax, ay, az, wx, wy, wz per line (header optional)\n"
    "  --odom-csv F   second odometry to add as `odom_alt`: t x y z qx qy qz qw [+ 21 values,\n"
    "                 the covariance's upper triangle row by row, x y z roll pitch yaw]\n"
    "  --gt-tum F     also write the rawlog's `gt` poses as a TUM file (for evo, superloc-eval)\n"
    "  --out FILE     output rawlog (one LiDAR observation per scan, label `lidar`)\n"
    "  --quiet        no summary on stdout\n";

struct Args {
    std::string kitti, pcd_dir, rosbag, poses, times, out, config, imu_csv, odom_csv, gt_tum;
    std::vector<std::string> sets;
    bool quiet = false, help = false, list = false, dump_config = false;
};

Args parse(int argc, char** argv) {
    Args a;
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        const auto value = [&] { return superloc::flagValue(argc, argv, i); };
        if (k == "--help" || k == "-h")
            a.help = true;
        else if (k == "--kitti")
            a.kitti = value();
        else if (k == "--pcd-dir")
            a.pcd_dir = value();
        else if (k == "--rosbag")
            a.rosbag = value();
        else if (k == "--list")
            a.list = true;
        else if (k == "--config")
            a.config = value();
        else if (k == "--set")
            a.sets.push_back(value());
        else if (k == "--dump-config")
            a.dump_config = true;
        else if (k == "--poses")
            a.poses = value();
        else if (k == "--times")
            a.times = value();
        else if (k == "--gt-tum")
            a.gt_tum = value();
        else if (k == "--imu-csv")
            a.imu_csv = value();
        else if (k == "--odom-csv")
            a.odom_csv = value();
        else if (k == "--out")
            a.out = value();
        else if (k == "--quiet")
            a.quiet = true;
        else
            throw std::runtime_error("unknown argument '" + k + "' (see --help)");
    }
    if (a.help || a.dump_config) return a;
    if (int(!a.kitti.empty()) + int(!a.pcd_dir.empty()) + int(!a.rosbag.empty()) != 1)
        throw std::runtime_error(
            "give exactly one of --kitti DIR, --pcd-dir DIR or --rosbag BAG (see --help)");
    if (a.list && a.rosbag.empty()) throw std::runtime_error("--list goes with --rosbag BAG");
    if (!a.rosbag.empty() && (!a.poses.empty() || !a.times.empty()))
        throw std::runtime_error(
            "--poses/--times are for --kitti/--pcd-dir; a bag's ground truth is a topic "
            "(--set rosbag.gt_topic=TOPIC)");
    if (a.out.empty() && !a.list) throw std::runtime_error("--out FILE.rawlog is required (see --help)");
    return a;
}

superloc::io::RosbagParams loadRosbagParams(const Args& a) {
    mrpt::config::CConfigFileMemory cfg;
    std::string source = "command line";
    if (!a.config.empty()) {
        source = a.config;
        std::ifstream in(a.config);
        if (!in) throw std::runtime_error("--config " + a.config + ": cannot open");
        std::stringstream text;
        text << in.rdbuf();
        cfg.setContent(text.str());
    }
    for (const auto& s : a.sets) superloc::applyOverride(cfg, s);
    return superloc::loadParams<superloc::io::RosbagParams>(
        cfg, "rosbag", a.sets.empty() ? source : source + " / --set");
}

/// --gt-tum: the `gt` poses of the written rawlog as TUM.
void writeGtTum(const Args& a, const std::string& gt_label) {
    if (a.gt_tum.empty()) return;
    superloc::io::RawlogParams rp;
    rp.gt_label = gt_label;
    rp.scan_period = 0;
    superloc::io::RawlogReader reader(a.out, rp);
    superloc::Trajectory gt;
    superloc::io::RawlogItem it;
    while (reader.next(it))
        if (it.kind == superloc::io::RawlogItem::Kind::GroundTruth) gt.push_back(it.pose());
    if (gt.empty()) throw std::runtime_error("--gt-tum: " + a.out + " has no `" + gt_label + "` poses");
    superloc::io::saveTum(a.gt_tum, gt);
}

int runRosbag(const Args& a, const superloc::io::RosbagParams& params,
              const superloc::io::ProgressFn& bar, superloc::io::ImportExtras extras) {
    if (a.list) {
        for (const auto& t : superloc::io::listRosbag(a.rosbag))
            std::cout << t.topic << "  " << t.type << "  " << t.messages << " messages\n";
        return 0;
    }
    extras.imu_label = params.imu_label;
    extras.odom_alt_label = params.odom_alt_label;
    const auto r = superloc::io::importRosbag(a.rosbag, params, a.out, bar, extras);
    for (const auto& [topic, n] : r.non_monotonic)
        std::cerr << "superloc-import: warning: " << a.rosbag << ": topic '" << topic << "': " << n
                  << " messages skipped (header.stamp did not increase)\n";
    if (!a.quiet)
        std::cout << a.out << ": " << r.scans << " scans (" << r.lidar_topic << ", "
                  << r.timed_scans << " with per-point time"
                  << (r.time_field.empty() ? "" : " '" + r.time_field + "'") << "), " << r.points
                  << " points, " << r.imu << " imu, " << r.odom_alt << " odom_alt, " << r.gt_poses
                  << " gt poses, " << r.dropped_points << " NaN/inf points dropped\n";
    writeGtTum(a, params.gt_label);
    return 0;
}

int run(int argc, char** argv) {
    const Args a = parse(argc, argv);
    if (a.help) {
        std::cout << kUsage;
        return 0;
    }
    const auto rosbag_params = loadRosbagParams(a);
    if (a.dump_config) {
        mrpt::config::CConfigFileMemory c;
        rosbag_params.saveToConfigFile(c, "rosbag");
        std::cout << c.getContent();
        return 0;
    }
    superloc::io::ProgressFn bar;
    if (isatty(STDERR_FILENO))
        bar = [](size_t done, size_t total) {
            std::fprintf(stderr, "\r%s %zu/%zu scans",
                         mrpt::system::progress(double(done) / total, 40).c_str(), done, total);
            if (done == total) std::fprintf(stderr, "\n");
        };
    superloc::io::ImportExtras extras;
    if (!a.imu_csv.empty()) extras.imu = superloc::io::loadImuCsv(a.imu_csv);
    if (!a.odom_csv.empty()) extras.odom_alt = superloc::io::loadOdomCsv(a.odom_csv);
    if (!a.rosbag.empty()) return runRosbag(a, rosbag_params, bar, extras);
    const auto r =
        a.kitti.empty()
            ? superloc::io::importPcdFolder(a.pcd_dir, a.poses, a.times, a.out, bar, extras)
            : superloc::io::importKitti(a.kitti, a.poses, a.times, a.out, bar, extras);
    if (!a.quiet)
        std::cout << a.out << ": " << r.scans << " scans, " << r.points << " points, " << r.gt_poses
                  << " gt poses, " << r.imu << " imu, " << r.odom_alt << " odom_alt, "
                  << r.dropped_points << " NaN/inf points dropped\n";
    writeGtTum(a, "gt");
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "superloc-import: " << superloc::oneLineError(e) << std::endl;
        return 1;
    }
}
