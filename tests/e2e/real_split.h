// The honest real-data protocol of the e2e tests (doc/design.md#8-evaluation): a real sequence imported once,
// its prior map built from one subset of its scans (even) at their GT poses, and another subset
// (odd) localized in it. Nothing here localizes a scan in a map that holds it.
#pragma once

#include <superloc/core/se3.h>
#include <superloc/io/importers.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/tum.h>
#include <superloc/map/map_builder.h>
#include <superloc/map/prior_map.h>
#include <superloc_testing/testing.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <memory>
#include <string>
#include <vector>

namespace superloc::testing {

struct RealSplit {
    std::string dir;        ///< fixture folder
    std::string rawlog;     ///< every scan (+ gt)
    std::string map;        ///< prior map from `map_scans`
    std::string gt_tum;     ///< GT of every scan
    bool ok = false;        ///< the shared data was there
};

/// Which of kitti00-mini's pose files a split is built and judged on (../shared/data/README.md):
/// KITTI's ground truth, a constant-velocity fill-in for scans 0-13, so a map built at it is
/// warped (the scans' walls 6 cm thick); or the LiDAR-consistent reference (`ref_lidar_tum.txt`),
/// the poses to judge accuracy on these scans by. campus-ouster has one (`gt_tum.txt`).
enum class KittiPoses { GroundTruth, Reference };

/// Imports `data` (kitti00-mini or campus-ouster) into DIR and builds the prior map from the
/// scans `map_scans` at `voxel` (superloc-map's defaults otherwise), both at `poses`' poses.
inline RealSplit prepareRealSplit(const std::string& name, const std::string& data, const std::string& map_scans,
                                  double voxel, KittiPoses poses = KittiPoses::GroundTruth) {
    namespace fs = std::filesystem;
    RealSplit s;
    s.dir = freshDir(name);
    const bool kitti = data == "kitti00-mini";
    s.gt_tum = sharedData(data + (!kitti                                ? "/gt_tum.txt"
                                  : poses == KittiPoses::Reference ? "/ref_lidar_tum.txt"
                                                                    : "/gt_velodyne_tum.txt"));
    if (!fs::exists(s.gt_tum)) return s;
    s.rawlog = s.dir + "/all.rawlog";
    if (kitti)
        io::importKitti(sharedData(data), s.gt_tum, "", s.rawlog);
    else
        io::importPcdFolder(sharedData(data + "/scans"), s.gt_tum, "", s.rawlog);
    map::MapBuildOptions o;
    o.rawlog = s.rawlog;
    o.poses_tum = s.gt_tum;
    o.voxel = voxel;
    o.normals = false;
    o.rawlog_params.scans = map_scans;
    map::MapBuilder b(o);
    b.setMinLoggingLevel(mrpt::system::LVL_WARN);
    s.map = s.dir + "/map_" + map_scans + ".pcd";
    io::savePointCloud(s.map, b.build());
    s.ok = true;
    return s;
}

/// A pose as `--initial-pose` takes it: "x y z qx qy qz qw".
inline std::string poseString(const SE3d& T) {
    const Eigen::Quaterniond q(T.linear());
    char b[256];
    std::snprintf(b, sizeof(b), "%.9f %.9f %.9f %.12f %.12f %.12f %.12f", T.translation().x(), T.translation().y(),
                  T.translation().z(), q.x(), q.y(), q.z(), q.w());
    return b;
}

/// The scans `scans` of a rawlog with their GT poses (interpolated at each scan's time).
inline void readScans(const std::string& rawlog, const std::string& scans, const Trajectory& gt,
                      std::vector<Scan>& out, std::vector<SE3d>& T_gt, double max_gap = 1.0) {
    io::RawlogParams rp;
    rp.scans = scans;
    io::RawlogReader r(rawlog, rp);
    io::RawlogItem it;
    while (r.next(it))
        if (it.kind == io::RawlogItem::Kind::Lidar) {
            const auto g = interpolateAt(gt, it.scan().t, max_gap, 1e-3);
            if (!g) continue;
            out.push_back(it.scan());
            T_gt.push_back(*g);
        }
}

}  // namespace superloc::testing
