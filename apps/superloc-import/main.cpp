// superloc-import (--kitti DIR | --pcd-dir DIR) [--poses TUM] [--times FILE] --out FILE.rawlog
// Converts a folder of scans into a rawlog (DESIGN §9); the work is io::importKitti /
// io::importPcdFolder.
#include <mrpt/system/progress.h>
#include <superloc/core/cli.h>
#include <superloc/core/errors.h>
#include <superloc/io/importers.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace {

const char* kUsage =
    "Usage: superloc-import (--kitti DIR | --pcd-dir DIR) [--poses TUM] [--times FILE] --out "
    "FILE.rawlog\n"
    "  --kitti DIR    KITTI odometry folder: DIR/velodyne/NNNNNN.bin and DIR/times.txt\n"
    "  --pcd-dir DIR  folder of PCD scans (sorted by file name)\n"
    "  --poses TUM    ground-truth poses (T_world_lidar), one per scan or matched by time;\n"
    "                 written as `gt` CObservationRobotPose observations\n"
    "  --times FILE   scan times [s], one per line (default: DIR/times.txt for KITTI, the\n"
    "                 --poses timestamps for a PCD folder)\n"
    "  --out FILE     output rawlog (one CObservationPointCloud per scan, label `lidar`)\n"
    "  --quiet        no summary on stdout\n";

struct Args {
    std::string kitti, pcd_dir, poses, times, out;
    bool quiet = false, help = false;
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
        else if (k == "--poses")
            a.poses = value();
        else if (k == "--times")
            a.times = value();
        else if (k == "--out")
            a.out = value();
        else if (k == "--quiet")
            a.quiet = true;
        else
            throw std::runtime_error("unknown argument '" + k + "' (see --help)");
    }
    if (a.help) return a;
    if (a.kitti.empty() == a.pcd_dir.empty())
        throw std::runtime_error("give exactly one of --kitti DIR or --pcd-dir DIR (see --help)");
    if (a.out.empty()) throw std::runtime_error("--out FILE.rawlog is required (see --help)");
    return a;
}

int run(int argc, char** argv) {
    const Args a = parse(argc, argv);
    if (a.help) {
        std::cout << kUsage;
        return 0;
    }
    superloc::io::ProgressFn bar;
    if (isatty(STDERR_FILENO))
        bar = [](size_t done, size_t total) {
            std::fprintf(stderr, "\r%s %zu/%zu scans",
                         mrpt::system::progress(double(done) / total, 40).c_str(), done, total);
            if (done == total) std::fprintf(stderr, "\n");
        };
    const auto r = a.kitti.empty()
                       ? superloc::io::importPcdFolder(a.pcd_dir, a.poses, a.times, a.out, bar)
                       : superloc::io::importKitti(a.kitti, a.poses, a.times, a.out, bar);
    if (!a.quiet)
        std::cout << a.out << ": " << r.scans << " scans, " << r.points << " points, " << r.gt_poses
                  << " gt poses, " << r.dropped_points << " NaN/inf points dropped\n";
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
