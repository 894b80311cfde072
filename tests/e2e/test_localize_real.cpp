// Localization on real data without IMU, by the honest protocol (real_split.h): the prior map is
// built from the even scans, the odd scans are localized in it with the default INI plus the
// sensor's facts (both data sets come motion-compensated: deskew off).
//  - kitti00-mini: 8 odd scans 0.2 s apart (5 Hz, ~1.7 m between them), from the pose at the
//    first odd scan and from a start 1.0 m, 1.0 m, 0.2 m and 10 deg of yaw away. Twice: with map
//    and poses at the LiDAR-consistent reference (ref_lidar_tum.txt, the split accuracy is judged
//    on), and at KITTI's ground truth, a constant-velocity fill-in for scans 0-13 that the scans
//    contradict (a warped map: what a drifting SLAM map does to a localizer).
//  - campus-ouster: 26 odd scans 2 s apart, a walk turning by up to ~90 deg between them (the
//    relocalization's local search keeps it on track; without it the turns lose it).
// Until 2026-11-30 the helper below ran the voxel association with 10 rounds (then the tested
// path, when the default was the kd-tree); it now runs the default INI, as users do. Measured
// with it: KITTI at the GT from the GT start ATE 0.179 m (voxel: 0.17-0.19), from the perturbed
// start 0.339 m (voxel: 0.22; the first two frames, `start_ambiguous`); campus 0.0156 m (voxel:
// 0.020).
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/io/map_tiles.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "e2e_run.h"
#include "real_split.h"

using namespace superloc;
using namespace superloc::localization;

namespace {
class RealSplitRuns : public ::testing::Test {
 protected:
    static void SetUpTestSuite() {
        kitti_ = superloc::testing::prepareRealSplit("real_split_kitti", "kitti00-mini", "even", 0.2);
        campus_ = superloc::testing::prepareRealSplit("real_split_campus", "campus-ouster", "even", 0.1);
        kitti_ref_ = superloc::testing::prepareRealSplit("real_split_kitti_ref", "kitti00-mini", "even", 0.1,
                                                         superloc::testing::KittiPoses::Reference);
    }
    static superloc::testing::LocalizeRun localize(const superloc::testing::RealSplit& s, const std::string& name,
                                                    std::vector<std::string> extra) {
        std::vector<std::string> args = {"--rawlog", s.rawlog, "--map", s.map, "--set", "rawlog.scans=odd",
                                         "--set", "features.deskew=false"};
        args.insert(args.end(), extra.begin(), extra.end());
        return superloc::testing::localizeAndCompare(args, s.dir + "/" + name, s.gt_tum, 1.5);
    }
    static superloc::testing::RealSplit kitti_, campus_, kitti_ref_;
};
superloc::testing::RealSplit RealSplitRuns::kitti_, RealSplitRuns::campus_, RealSplitRuns::kitti_ref_;
}  // namespace

// The KITTI split accuracy is judged on (map and poses at the LiDAR-consistent reference), the
// default INI from the reference pose: every frame within 2 cm (issue 34's accuracy bound) and
// `ok`, its reported sigma neither hiding the error nor far above it. Measured (2026-11-30):
// ATE 0.0086 m, worst 0.0116 m / 0.09 deg, every frame ok, mean 3-D sigma 0.014 m against a mean
// error 0.008 m.
TEST_F(RealSplitRuns, KittiReferenceSplitDefaultIniEveryFrameOk) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/ref_lidar_tum.txt");
    const auto r = localize(kitti_ref_, "reference", {"--initial-pose-tum", kitti_ref_.gt_tum});
    ASSERT_EQ(r.frames.size(), 8u);
    EXPECT_LT(r.ate, 0.02) << "ATE RMSE [m]";
    EXPECT_LT(r.worst_deg, 0.2);
    EXPECT_EQ(r.count(Health::Ok), 8u);
    double sigma = 0, err = 0;
    for (size_t i = 0; i < r.frames.size(); ++i) {
        sigma += std::sqrt(r.frames[i].cov.topLeftCorner<3, 3>().trace());  // 3-D position sigma
        err += r.err_m[i];
    }
    EXPECT_GT(sigma, err / 3) << "the position sigma hides the error";
    EXPECT_LT(sigma, err * 3) << "the position sigma is far above the error";
    std::cout << "kitti reference split, default INI: ATE " << r.ate << " m, worst " << r.worst_m << " m / "
              << r.worst_deg << " deg, mean sigma " << sigma / 8 << " m against mean error " << err / 8 << " m\n";
}

TEST_F(RealSplitRuns, KittiOddScansInEvenMapFromGroundTruthStart) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    for (const std::string method : {"superloc", "icp"}) {
        const auto r = localize(kitti_, "gt_start_" + method, {"--initial-pose-tum", kitti_.gt_tum, "--method", method});
        EXPECT_EQ(r.frames.size(), 8u);
        EXPECT_EQ(r.summary.diverged, 0u) << method;
        EXPECT_LT(r.ate, 0.25) << method << ": ATE RMSE [m]";
        EXPECT_LT(r.worst_deg, 1.0) << method;
        std::cout << "kitti split, " << method << ", GT start: ATE " << r.ate << " m, worst " << r.worst_m << " m / "
                  << r.worst_deg << " deg\n";
    }
    // The kd-tree association of the default INI settles up to 1.1 m behind along the road when
    // it may not search (the basin issue's finding), and says so: no frame that far off is `ok`.
    // With the relocalization on (the default), the frames in doubt are searched again and the
    // run comes back to the road.
    const std::vector<std::string> nearest_args = {"--rawlog", kitti_.rawlog, "--map", kitti_.map, "--set",
                                                   "rawlog.scans=odd", "--set", "features.deskew=false",
                                                   "--initial-pose-tum", kitti_.gt_tum, "--method", "icp"};
    auto args = nearest_args;
    args.insert(args.end(), {"--set", "relocalization.enabled=false"});
    const auto alone = superloc::testing::localizeAndCompare(args, kitti_.dir + "/gt_start_nearest_alone", kitti_.gt_tum, 1.5);
    EXPECT_GT(alone.worst_m, 0.5);
    EXPECT_EQ(alone.confidentlyWrong(), 0u);
    const auto nearest =
        superloc::testing::localizeAndCompare(nearest_args, kitti_.dir + "/gt_start_nearest", kitti_.gt_tum, 1.5);
    // Measured: ATE 0.18 m with (0.43 m without; 0.32-0.46 / 0.71 m before the second frame
    // measured its motion against the first scan), frames 4-7 within 6 cm.
    EXPECT_LT(nearest.ate, alone.ate);
    EXPECT_EQ(nearest.confidentlyWrong(), 0u);
    ASSERT_EQ(nearest.err_m.size(), 8u);
    for (size_t i = 4; i < 8; ++i) EXPECT_LT(nearest.err_m[i], 0.1) << "frame " << i;
    std::cout << "kitti split, icp, nearest, GT start: ATE " << alone.ate << " m (worst " << alone.worst_m
              << ") without relocalization, " << nearest.ate << " m (worst " << nearest.worst_m << ") with\n";
}

// Without IMU the second frame's velocity is unknown. It used to start wide from the first
// frame's pose, 1.7 m behind at 5 Hz, and settled 0.46 m behind in the smeared start of the
// KITTI split (doc/results.md, "KITTI split"). It now measures its motion against the first
// scan and is solved from there as a tracked frame: 0.13 m, near its floor from the GT pose.
// campus-ouster (2 s between odd scans, so every frame's velocity is unknown): every frame is
// predicted that way or, on turns of 30-90 deg the last scan cannot follow, searched.
TEST_F(RealSplitRuns, UnknownVelocityIsMeasuredAgainstTheLastScan) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const std::vector<std::string> kitti_args = {"--rawlog", kitti_.rawlog, "--map", kitti_.map, "--set",
                                                 "rawlog.scans=odd", "--set", "features.deskew=false",
                                                 "--initial-pose-tum", kitti_.gt_tum, "--method", "icp"};
    auto assumed_args = kitti_args;
    assumed_args.insert(assumed_args.end(), {"--set", "localization.motion_from_last_scan=false"});
    const auto measured =
        superloc::testing::localizeAndCompare(kitti_args, kitti_.dir + "/motion_measured", kitti_.gt_tum, 1.5);
    const auto assumed =
        superloc::testing::localizeAndCompare(assumed_args, kitti_.dir + "/motion_assumed", kitti_.gt_tum, 1.5);
    ASSERT_EQ(measured.frames.size(), 8u);
    ASSERT_EQ(assumed.frames.size(), 8u);
    EXPECT_TRUE(measured.frames[1].motion_from_scan);
    EXPECT_FALSE(measured.frames[1].coarse_start);
    EXPECT_TRUE(assumed.frames[1].coarse_start);
    EXPECT_FALSE(assumed.frames[1].motion_from_scan);
    EXPECT_LT(measured.err_m[1], 0.25);  // measured 0.13 m
    EXPECT_GT(assumed.err_m[1], 0.3);    // measured 0.43 m
    EXPECT_LT(measured.ate, 0.25);       // measured 0.18 m (assumed: 0.32 m)
    EXPECT_LT(measured.ate, assumed.ate);
    EXPECT_EQ(measured.confidentlyWrong(), 0u);
    std::cout << "kitti split, icp, default INI: ATE " << measured.ate << " m, frame 1 " << measured.err_m[1]
              << " m (velocity assumed: ATE " << assumed.ate << " m, frame 1 " << assumed.err_m[1] << " m)\n";

    const auto campus = superloc::testing::localizeAndCompare(
        {"--rawlog", campus_.rawlog, "--map", campus_.map, "--set", "rawlog.scans=odd", "--set",
         "features.deskew=false", "--initial-pose-tum", campus_.gt_tum},
        campus_.dir + "/motion_measured", campus_.gt_tum, 2.5);
    ASSERT_EQ(campus.frames.size(), 26u);
    size_t from_scan = 0;
    for (const auto& f : campus.frames) from_scan += f.motion_from_scan;
    EXPECT_GE(from_scan, 15u);  // measured 21 of 26
    EXPECT_LT(campus.worst_m, 0.10);  // measured 0.036 m
    EXPECT_EQ(campus.count(Health::Lost), 0u);
    std::cout << "campus split, default INI: " << from_scan << " of 26 frames predicted by the last scan, ATE "
              << campus.ate << " m, worst " << campus.worst_m << " m\n";
}

// campus-ouster turns by 30-100 deg between odd scans on 10 of its 26 frames. From no motion the
// last scan's registration cannot follow such a turn: the frame is solved wide in the prior map
// and searched (100-250 ms). The first guess turns the last scan about the vertical in 30 deg
// steps and starts from the turn most features agree with (doc/localizer.md, "Unknown
// velocity"): more frames measured, fewer searched, none wrong.
TEST_F(RealSplitRuns, CampusTurnsAreMeasuredFromATurnedFirstGuess) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const std::vector<std::string> common = {"--rawlog", campus_.rawlog, "--map", campus_.map, "--set",
                                             "rawlog.scans=odd", "--set", "features.deskew=false",
                                             "--initial-pose-tum", campus_.gt_tum};
    auto off_args = common;
    off_args.insert(off_args.end(), {"--set", "localization.last_scan_yaw_step=0"});
    const auto guess = superloc::testing::localizeAndCompare(common, campus_.dir + "/yaw_guess", campus_.gt_tum, 2.5);
    const auto none = superloc::testing::localizeAndCompare(off_args, campus_.dir + "/yaw_none", campus_.gt_tum, 2.5);
    ASSERT_EQ(guess.frames.size(), 26u);
    ASSERT_EQ(none.frames.size(), 26u);
    size_t measured_guess = 0, measured_none = 0, searched_guess = 0, searched_none = 0;
    for (const auto& f : guess.frames) measured_guess += f.motion_from_scan, searched_guess += f.recovered;
    for (const auto& f : none.frames) measured_none += f.motion_from_scan, searched_none += f.recovered;
    EXPECT_GE(measured_guess, measured_none + 3);  // measured 23 against 19
    EXPECT_LE(searched_guess + 3, searched_none);  // measured 5 against 10
    EXPECT_LT(guess.worst_m, 0.10);
    EXPECT_EQ(guess.count(Health::Lost), 0u);
    EXPECT_EQ(guess.confidentlyWrong(), 0u);
    std::cout << "campus split: " << measured_guess << " frames measured against the last scan, " << searched_guess
              << " searched (from no motion only: " << measured_none << ", " << searched_none << "), ATE "
              << guess.ate << " m\n";
}

// Doubt searches are rate-limited (doc/health.md, "Triggers"): in the warped map the odd frames
// from 3 on end their rounds still moving (in doubt); after a doubt's search confirmed a frame's
// own pose (not_better), the frames in doubt within [relocalization] doubt_search_period (1 s)
// are not searched but kept, degraded (reloc_result `deferred`). A search that moved the pose
// holds none back.
TEST_F(RealSplitRuns, KittiWarpedMapDoubtSearchesRateLimited) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    const auto limited = localize(kitti_, "doubt_limited",
                                  {"--initial-pose-tum", kitti_.gt_tum, "--set", "relocalization.doubt_search_period=1"});
    const auto every = localize(kitti_, "doubt_every", {"--initial-pose-tum", kitti_.gt_tum});
    ASSERT_EQ(limited.frames.size(), 8u);
    ASSERT_EQ(every.frames.size(), 8u);
    const auto searches = [](const superloc::testing::LocalizeRun& r) {
        size_t n = 0;
        for (const auto& f : r.frames) n += f.reloc.trigger == "doubt" && f.reloc.outcome != RelocOutcome::Deferred;
        return n;
    };
    size_t deferred = 0;
    double confirmed = std::numeric_limits<double>::quiet_NaN();  // the last doubt search that confirmed its frame's pose
    for (const auto& f : limited.frames) {
        if (f.reloc.outcome == RelocOutcome::Deferred) {
            ++deferred;
            EXPECT_EQ(f.reloc.trigger, "doubt");
            EXPECT_NE(f.health, Health::Ok) << "a deferred frame at t=" << f.t;
            EXPECT_LT(f.t - confirmed, 1.0) << "deferred at t=" << f.t << " (NaN: no confirming search before)";
        } else if (f.reloc.trigger == "doubt") {
            if (f.reloc.outcome == RelocOutcome::NotBetter) confirmed = f.t;
            if (f.reloc.outcome == RelocOutcome::Accepted) confirmed = std::numeric_limits<double>::quiet_NaN();
        }
    }
    for (const auto& f : every.frames) EXPECT_NE(f.reloc.outcome, RelocOutcome::Deferred);
    EXPECT_GE(deferred, 1u);
    EXPECT_LT(searches(limited), searches(every));
    EXPECT_EQ(limited.confidentlyWrong(), 0u);
    EXPECT_LT(limited.ate, 0.25) << "ATE RMSE [m]";
    std::cout << "kitti split, warped map, GT start: " << searches(limited) << " doubt searches, " << deferred
              << " deferred, ATE " << limited.ate << " m, " << limited.count(Health::Ok) << " ok; every frame in doubt searched: "
              << searches(every) << " searches, ATE " << every.ate << " m, " << every.count(Health::Ok) << " ok\n";
}

// Why the KITTI split's first frames have a floor of ~0.15 m (doc/results.md, "KITTI split"):
// KITTI's ground truth and the scans disagree at the start of sequence 00. Scan 1, localized
// from its GT pose in a map of scan 0 alone, settles 0.17 m behind its GT pose along the road;
// in a map of scan 2 alone, 0.15 m ahead: the scans moved ~0.16 m less per 0.1 s than the GT
// says (PCL's GICP measures the same, with or without the ground points). By scan 15 the two
// agree within 2 cm. A map built from the even scans at the GT poses is therefore smeared along
// the road at the start.
TEST_F(RealSplitRuns, KittiGroundTruthAndScansDisagreeAtTheStart) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    const Trajectory gt = io::loadTum(kitti_.gt_tum);
    const auto alongRoad = [&](const std::string& map_scans, int scan) {
        const auto one = superloc::testing::prepareRealSplit("kitti_scan_" + map_scans, "kitti00-mini", map_scans, 0.2);
        const std::string sel = std::to_string(scan) + ":" + std::to_string(scan + 1);
        const auto r = superloc::testing::localizeAndCompare(
            {"--rawlog", one.rawlog, "--map", one.map, "--set", "rawlog.scans=" + sel, "--set",
             "features.deskew=false", "--initial-pose-tum", kitti_.gt_tum, "--method", "icp", "--set",
             "localization.max_corr_dist_init=1.0"},
            one.dir + "/scan_" + sel, kitti_.gt_tum, 1.5);
        EXPECT_EQ(r.frames.size(), 1u);
        if (r.frames.empty()) return 0.0;
        return (gt.at(static_cast<size_t>(scan)).pose.inverse() * r.frames[0].T_map_lidar).translation().x();
    };
    const double behind = alongRoad("0:1", 1), ahead = alongRoad("2:3", 1), late = alongRoad("14:15", 15);
    EXPECT_LT(behind, -0.10);  // measured -0.17 m
    EXPECT_GT(ahead, 0.10);    // measured +0.15 m
    EXPECT_LT(std::abs(late), 0.05);  // measured 0.00 m
    std::cout << "kitti: scan 1 from its GT pose, along the road: " << behind << " m in scan 0's map, " << ahead
              << " m in scan 2's; scan 15 in scan 14's: " << late << " m\n";
}

// The same start (1.0 m, 1.0 m, 0.2 m and 10 deg of yaw off) with the default INI (kd-tree
// association). The start check (doc/health.md, "Start") finds two seeds fitting alike 0.6 m
// apart along the road (inlier ratio 0.624 and 0.621) and the frame's own solve far worse
// (0.374, 1.06 m / 9 deg off): it takes the best seed, reported `start_ambiguous`. Measured:
// ATE 0.337 m, frame 0 0.82 m off (degraded), frame 1 0.45 m (degraded), from frame 2 on
// within 0.13 m. Before (own solve kept): ATE 0.778 m, frames 1-2 1.2-1.5 m / 9 deg off, `ok`.
TEST_F(RealSplitRuns, KittiDefaultIniFromPerturbedStartNeverConfidentlyWrong) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    SE3d T0 = io::loadTum(kitti_.gt_tum).at(1).pose;
    T0.translation() += Vec3d(1.0, 1.0, 0.2);
    T0.linear() = T0.linear() * Eigen::AngleAxisd(10 * M_PI / 180, Vec3d::UnitZ()).toRotationMatrix();
    const auto r = superloc::testing::localizeAndCompare(
        {"--rawlog", kitti_.rawlog, "--map", kitti_.map, "--set", "rawlog.scans=odd", "--method", "icp",
         "--initial-pose", superloc::testing::poseString(T0)},
        kitti_.dir + "/perturbed_default", kitti_.gt_tum, 1.5);
    ASSERT_EQ(r.frames.size(), 8u);
    EXPECT_EQ(r.confidentlyWrong(), 0u);
    EXPECT_NE(r.frames[0].health, Health::Ok);
    EXPECT_EQ(r.frames[0].health_reason, "start_ambiguous");
    EXPECT_LT(r.ate, 0.4);
    for (size_t i = 2; i < 8; ++i) EXPECT_LT(r.err_m[i], 0.2) << "odd frame " << i;
    std::cout << "kitti split, default INI, start 1.0/1.0/0.2 m 10 deg off: ATE " << r.ate << " m, frame 0 "
              << r.err_m[0] << " m (" << healthName(r.frames[0].health) << " " << r.frames[0].health_reason << ")\n";
}

TEST_F(RealSplitRuns, KittiOddScansInEvenMapFromPerturbedStart) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    const Trajectory gt = io::loadTum(kitti_.gt_tum);
    SE3d T0 = gt.at(1).pose;  // the first odd scan
    T0.translation() += Vec3d(1.0, 1.0, 0.2);
    T0.linear() = T0.linear() * Eigen::AngleAxisd(10 * M_PI / 180, Vec3d::UnitZ()).toRotationMatrix();
    for (const std::string method : {"superloc", "icp"}) {
        const auto r = localize(kitti_, "perturbed_" + method, {"--initial-pose", superloc::testing::poseString(T0), "--method", method});
        EXPECT_EQ(r.frames.size(), 8u);
        EXPECT_LT(r.ate, 0.35) << method << ": ATE RMSE [m]";
        std::cout << "kitti split, " << method << ", start 1.0/1.0/0.2 m 10 deg off: ATE " << r.ate << " m, worst "
                  << r.worst_m << " m / " << r.worst_deg << " deg\n";
    }
}

TEST_F(RealSplitRuns, CampusOddScansInEvenMap) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const auto r = localize(campus_, "campus", {"--initial-pose-tum", campus_.gt_tum});
    EXPECT_EQ(r.frames.size(), 26u);
    EXPECT_EQ(r.summary.diverged, 0u);
    EXPECT_LT(r.ate, 0.05) << "ATE RMSE [m]";
    EXPECT_LT(r.worst_m, 0.15);
    std::cout << "campus split: ATE " << r.ate << " m, worst " << r.worst_m << " m / " << r.worst_deg << " deg, "
              << r.summary.recovered << " frames recovered\n";
}

TEST_F(RealSplitRuns, CampusWithoutRelocalizationTheTurnsLoseTrack) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const auto r = localize(campus_, "campus_no_relocalization",
                            {"--initial-pose-tum", campus_.gt_tum, "--set", "relocalization.enabled=false"});
    EXPECT_EQ(r.summary.recovered, 0u);
    EXPECT_GT(r.worst_m, 0.3);
    std::cout << "campus split without relocalization: worst " << r.worst_m << " m / " << r.worst_deg << " deg\n";
}

// A map too large for memory is split into tiles on disk and localized in through the tiles
// around the robot (doc/map.md, "Tiled maps"). The campus split's even-scan map in 5 m tiles,
// loaded within 15 m of the robot and again after every 4 m it moves: the walk (18 x 12 m)
// reloads the tiles several times, each load smaller than the whole map, and the odd scans are
// localized as in the whole map (default INI, kd-tree association).
TEST_F(RealSplitRuns, CampusInMapTilesLoadedAroundTheRobot) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const PointCloud whole = io::loadPointCloud(campus_.map);
    const std::string tiles = campus_.dir + "/tiles_5m";
    std::filesystem::remove_all(tiles);
    const io::MapTileIndex index = io::writeMapTiles(whole, 5.0, tiles);
    ASSERT_EQ(index.totalPoints(), whole.size());
    const std::vector<std::string> common = {"--rawlog", campus_.rawlog, "--set", "rawlog.scans=odd",
                                             "--set", "features.deskew=false", "--initial-pose-tum", campus_.gt_tum};
    auto whole_args = common;
    whole_args.insert(whole_args.end(), {"--map", campus_.map});
    auto tiled_args = common;
    tiled_args.insert(tiled_args.end(),
                      {"--map", tiles, "--set", "map.tile_radius=15", "--set", "map.tile_reload=4"});
    const auto w = superloc::testing::localizeAndCompare(whole_args, campus_.dir + "/whole_map", campus_.gt_tum, 2.5);
    const auto t = superloc::testing::localizeAndCompare(tiled_args, campus_.dir + "/tiled_map", campus_.gt_tum, 2.5);
    ASSERT_EQ(t.frames.size(), 26u);
    EXPECT_GE(t.summary.map_reloads, 2u);
    EXPECT_LT(t.summary.map_points_max, w.summary.map_points);
    EXPECT_LT(t.worst_m, 0.10);
    EXPECT_LT(t.ate, w.ate + 0.01);
    EXPECT_EQ(t.confidentlyWrong(), 0u);
    std::cout << "campus split, tiles of 5 m within 15 m: ATE " << t.ate << " m (whole map " << w.ate << " m), worst "
              << t.worst_m << " m, " << t.summary.map_reloads << " reloads, at most " << t.summary.map_points_max
              << " of " << w.summary.map_points << " points, longest load " << t.summary.map_reload_s_max
              << " s, longest wait " << t.summary.map_reload_wait_s_max << " s\n";

    // A corrupt tile that only a reload reads (tile (-4, 2), 18 m from the start, near the walk's
    // far end): the run stops there with a one-line error naming the tile, and the frames before
    // it are in trajectory.tum.
    const std::string bad_tiles = campus_.dir + "/tiles_5m_bad";
    std::filesystem::remove_all(bad_tiles);
    std::filesystem::copy(tiles, bad_tiles);
    ASSERT_TRUE(std::filesystem::exists(bad_tiles + "/tile_-4_2.pcd"));
    std::ofstream(bad_tiles + "/tile_-4_2.pcd", std::ios::trunc) << "# .PCD v0.7\nFIELDS x y\nnot a pcd\n";
    {
        app::LocalizeApp a;
        a.setMinLoggingLevel(mrpt::system::LVL_ERROR);
        const std::string out = campus_.dir + "/tiled_bad";
        ASSERT_EQ(a.initialize({superloc::testing::sourcePath("ini/localize.ini"), "--rawlog", campus_.rawlog, "--map",
                                bad_tiles, "--set", "rawlog.scans=odd", "--set", "features.deskew=false", "--set",
                                "map.tile_radius=15", "--set", "map.tile_reload=4", "--initial-pose-tum",
                                campus_.gt_tum, "--out", out}),
                  app::LocalizeApp::Action::Run);
        std::string error;
        try {
            a.run();
        } catch (const std::exception& e) {
            error = e.what();
        }
        EXPECT_NE(error.find("tile_-4_2.pcd"), std::string::npos) << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << error;
        const size_t kept = io::loadTum(out + "/trajectory.tum").size();
        EXPECT_GT(kept, 5u);
        EXPECT_LT(kept, 26u);
        std::cout << "corrupt tile: stopped after " << kept << " frames: " << error << "\n";
    }

    // A global start needs the whole map: with tiles it is a one-line error before any frame.
    app::LocalizeApp a;
    a.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    ASSERT_EQ(a.initialize({superloc::testing::sourcePath("ini/localize.ini"), "--rawlog", campus_.rawlog, "--map", tiles,
                            "--initial-pose", "auto", "--out", campus_.dir + "/tiled_auto"}),
              app::LocalizeApp::Action::Run);
    try {
        a.run();
        ADD_FAILURE() << "--initial-pose auto ran on a tiled map";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("tiled map"), std::string::npos) << e.what();
    }
}
