// Sweeps placed with the GT trajectory (each point at its firing time, derived from azimuth as
// the localizer does) lie on gt_map.ply: median distance <= 1.5 x range noise.
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/rawlog.h>
#include <superloc/sim/noise.h>
#include <superloc/sim/raycaster.h>

#include "sim_test_utils.h"

using namespace superloc;
using namespace superloc::sim;
using namespace superloc::app;

namespace {

void checkScansOnMap(const std::string& world, const std::vector<std::string>& sets,
                     bool expect_distortion = false) {
    SCOPED_TRACE(world);
    const std::string dir = superloc::testing::freshDir("sim_scan_on_map_" + world);
    const SimConfig cfg = simtest::worldConfig(world, sets);
    SimApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    app.initialize(cfg, dir);
    app.run();
    const SimScene scene = makeScene(cfg);

    const PointCloud gt_map = io::loadPointCloud(dir + "/gt_map.ply");
    ASSERT_GT(gt_map.size(), 10000u);
    const simtest::NearestDistance dist(gt_map.points, 0.25);

    io::RawlogReader reader(dir + "/sequence.rawlog");  // default [rawlog]: 0.1 s, CCW, 180 deg
    io::RawlogItem item;
    std::vector<double> d_deskewed, d_end_pose;
    size_t scans = 0;
    while (reader.next(item)) {
        if (item.kind != io::RawlogItem::Kind::Lidar) continue;
        const Scan& s = item.scan();
        ASSERT_EQ(s.rel_time.size(), s.size());
        ++scans;
        for (size_t i = 0; i < s.size(); i += 7) {
            ASSERT_LE(s.rel_time[i], 1e-6);
            ASSERT_GE(s.rel_time[i], -cfg.lidar.period() - 1e-6);
            const SE3d T = scene.trajectory.pose(s.t + s.rel_time[i]) * s.T_imu_lidar;
            d_deskewed.push_back(dist((T * s.points[i].cast<double>()).cast<float>()));
            const SE3d T_end = scene.trajectory.pose(s.t) * s.T_imu_lidar;  // no per-point time
            d_end_pose.push_back(dist((T_end * s.points[i].cast<double>()).cast<float>()));
        }
    }
    EXPECT_GE(scans, 19u);
    ASSERT_GT(d_deskewed.size(), 1000u);
    const double med = simtest::median(d_deskewed);
    EXPECT_LE(med, 1.5 * cfg.lidar.range_noise) << "median distance to gt_map " << med;
    EXPECT_GT(med, 0.2 * cfg.lidar.range_noise) << "range noise seems missing";
    // One pose per sweep is visibly worse on the structure around (most points lie on planes
    // parallel to the motion, which hide it): the motion distortion is real.
    const double p95 = simtest::quantile(d_deskewed, 0.95),
                 p95_end = simtest::quantile(d_end_pose, 0.95);
    EXPECT_LT(p95, 4 * cfg.lidar.range_noise);
    if (expect_distortion) {
        EXPECT_GT(p95_end, 2 * p95) << "p95 deskewed " << p95 << ", end-of-sweep pose " << p95_end;
    }
}

}  // namespace

TEST(ScanOnMap, OfficeHandheld) { checkScansOnMap("office", {"sim.duration=2"}); }

// The car at full speed in the corridor's open area, turning: the sweep is strongly distorted,
// so this fails unless the per-point times are right.
TEST(ScanOnMap, CorridorCarTurningAtSpeed) {
    checkScansOnMap("corridor",
                    {"corridor.length=30", "corridor.open_size=30", "sim.duration=16",
                     "sim.gt_map_max_distance=12"},
                    true);
}

TEST(ScanOnMap, CaveHandheld) { checkScansOnMap("cave", {"sim.duration=2"}); }

// The first sweep of the rawlog is exactly what simulateSweep gives, and the firing times the
// reader derives from azimuth equal the simulator's own per-point times.
TEST(ScanOnMap, RawlogSweepMatchesSimulatorFiringTimes) {
    const std::string dir = superloc::testing::freshDir("sim_firing_times");
    const SimConfig cfg =
        simtest::worldConfig("office", {"sim.duration=0.35", "sim.gt_map_spacing=0.2"});
    SimApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    app.initialize(cfg, dir);
    app.run();
    const SimScene scene = makeScene(cfg);
    const RayCaster caster(scene.world.mesh);
    std::mt19937_64 rng(streamSeed(cfg.sim.seed, "lidar"));
    const Scan ref = simulateSweep(caster, scene.world.mesh, scene.trajectory, cfg.lidar,
                                   cfg.sim.start_time + cfg.lidar.period(), rng);

    io::RawlogReader reader(dir + "/sequence.rawlog");
    io::RawlogItem item;
    while (reader.next(item) && item.kind != io::RawlogItem::Kind::Lidar) {
    }
    ASSERT_EQ(item.kind, io::RawlogItem::Kind::Lidar);
    const Scan& s = item.scan();
    ASSERT_EQ(s.size(), ref.size());
    EXPECT_NEAR(s.t, ref.t, 1e-6);
    for (size_t i = 0; i < s.size(); ++i) {
        ASSERT_LT((s.points[i] - ref.points[i]).norm(), 1e-5f);
        ASSERT_NEAR(s.rel_time[i], ref.rel_time[i], 2e-5) << "point " << i;
    }
}

// A platform box behind the sensor removes exactly the returns straight behind it.
TEST(ScanOnMap, SelfOcclusionBoxHidesTheRear) {
    SimConfig cfg = simtest::worldConfig(
        "office", {"sim.duration=1", "lidar.self_min_x=0", "lidar.self_max_x=0"});  // no operator
    const SimScene scene = makeScene(cfg);
    const RayCaster caster(scene.world.mesh);
    const auto behind = [](const Scan& s) {
        size_t n = 0;
        for (const auto& p : s.points)
            if (p.x() < -0.3f && std::abs(p.y()) < 0.1f * -p.x() && std::abs(p.z()) < 0.1f * -p.x())
                ++n;
        return n;
    };
    std::mt19937_64 rng1(1), rng2(1);
    const double t = cfg.sim.start_time + 0.5;
    const Scan open = simulateSweep(caster, scene.world.mesh, scene.trajectory, cfg.lidar, t, rng1);
    cfg.lidar.self_min_x = -1.0, cfg.lidar.self_max_x = -0.2;
    cfg.lidar.self_min_y = -0.2, cfg.lidar.self_max_y = 0.2;
    cfg.lidar.self_min_z = -1.0, cfg.lidar.self_max_z = 1.0;
    const Scan blocked =
        simulateSweep(caster, scene.world.mesh, scene.trajectory, cfg.lidar, t, rng2);
    EXPECT_GT(behind(open), 20u);
    EXPECT_EQ(behind(blocked), 0u);
    EXPECT_GT(blocked.size(), open.size() / 2);  // only a rear sector is lost
}
