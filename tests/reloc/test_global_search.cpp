// Global search on synthetic maps (doc/relocalization.md): pose recovery, the scan's own
// gravity estimate, region restriction, degenerate inputs, a featureless corridor's flat scores.
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/map/prior_map.h>
#include <superloc/reloc/global_search.h>
#include <superloc_testing/testing.h>


#include "synthetic_scenes.h"

using namespace superloc;
using namespace superloc::reloc;
using superloc::testing::corridor;
using superloc::testing::lHall;
using superloc::testing::scanFrom;

namespace {

// What the search itself must reach for a fine ICP to converge from it: a search cell with its
// dilation (0.25 m) and a yaw step (1.5 deg). The synthetic floor lies exactly on a voxel face of
// the registration voxel map (z = 0), where half the floor points find no voxel, so the
// point-to-plane refinement is rejected by its guard here and the leaf pose is what comes back;
// on the real data the refinement brings it to a few cm (test_global_search_real.cpp).
constexpr double kTolM = 0.3, kTolDeg = 2.0;
/// A runner-up this close to the best makes a search ambiguous: the default of the Localizer's
/// [relocalization] ambiguity_ratio, which decides what its lost-frame search verifies.
constexpr double kAmbiguous = 0.9;

map::PriorMap makeMap(const std::vector<Vec3f>& pts) {
    PointCloud c;
    c.points = pts;
    return map::PriorMap(c, map::MapParams{});
}

double yawDiffDeg(const SE3d& a, const SE3d& b) { return std::abs(rotationAngle(a, b)) / kDeg; }

}  // namespace

TEST(GlobalSearchParams, SaveLoadValidate) {
    GlobalSearchParams p;
    p.resolution = 0.3;
    p.max_hypotheses = 7;
    p.refine = false;
    mrpt::config::CConfigFileMemory cfg;
    p.saveToConfigFile(cfg, "global_search");
    const mrpt::config::CConfigFileMemory text(cfg.getContent());
    const auto q = loadParams<GlobalSearchParams>(text, "global_search", "t.ini");
    EXPECT_DOUBLE_EQ(q.resolution, 0.3);
    EXPECT_EQ(q.max_hypotheses, 7);
    EXPECT_FALSE(q.refine);
    mrpt::config::CConfigFileMemory bad;
    bad.write("global_search", "bands", "40");
    EXPECT_THROW(loadParams<GlobalSearchParams>(bad, "global_search", "t.ini"), ConfigError);
    mrpt::config::CConfigFileMemory typo;
    typo.write("global_search", "resolutoin", "0.2");
    EXPECT_THROW(loadParams<GlobalSearchParams>(typo, "global_search", "t.ini"), ConfigError);
}

TEST(GlobalSearch, RecoversPoseInLHall) {
    const auto pts = lHall();
    const auto m = makeMap(pts);
    GlobalSearch gs(m, GlobalSearchParams{});
    EXPECT_GT(gs.memoryBytes(), 0u);
    for (const auto& T : {makePoseRPY(3.2, 5.7, 1.4, 0, 0, 37 * kDeg), makePoseRPY(15.5, 4.1, 1.1, 0, 0, -120 * kDeg),
                          makePoseRPY(4.3, 17.2, 1.8, 0, 0, 170 * kDeg)}) {
        const auto scan = scanFrom(pts, T);
        const auto r = gs.search(scan, Mat3d::Identity());
        ASSERT_FALSE(r.hypotheses.empty()) << r.failure;
        const auto& best = r.hypotheses[0];
        EXPECT_LT(translationDistance(best.T_map_lidar, T), kTolM) << best.T_map_lidar.translation().transpose();
        EXPECT_LT(yawDiffDeg(best.T_map_lidar, T), kTolDeg);
        EXPECT_EQ(r.gravity, GravitySource::Given);
        EXPECT_NEAR(r.sensor_height, T.translation().z(), 0.05);
        EXPECT_GT(best.score, 0.8);
        EXPECT_LT(r.runner_up_ratio, kAmbiguous);
        // The search leaf itself is within a cell and a yaw step.
        EXPECT_LT((best.T_map_lidar_search.translation() - T.translation()).head<2>().norm(), 0.3);
    }
}

TEST(GlobalSearch, GroundPlaneLevelsATiltedScan) {
    const auto pts = lHall();
    const auto m = makeMap(pts);
    GlobalSearch gs(m, GlobalSearchParams{});
    const SE3d T = makePoseRPY(12.0, 3.5, 1.3, 12 * kDeg, -25 * kDeg, 65 * kDeg);
    const auto scan = scanFrom(pts, T);
    // The plane alone: roll/pitch within 1 deg, height within 5 cm.
    const auto g = estimateGroundPlane(scan, GroundPlaneParams{});
    ASSERT_TRUE(g.found);
    const Vec3d up_lidar = T.linear().transpose() * Vec3d::UnitZ();
    EXPECT_LT(std::acos(std::min(1.0, g.normal_lidar.dot(up_lidar))) / kDeg, 1.0);
    EXPECT_NEAR(g.height, 1.3, 0.05);
    EXPECT_LT((g.R_level_lidar * up_lidar - Vec3d::UnitZ()).norm(), 0.02);
    EXPECT_NEAR(yawOf(g.R_level_lidar), 0.0, 1e-9);
    // The whole search without an IMU.
    const auto r = gs.search(scan, std::nullopt);
    EXPECT_EQ(r.gravity, GravitySource::GroundPlane);
    ASSERT_FALSE(r.hypotheses.empty()) << r.failure;
    EXPECT_LT(translationDistance(r.hypotheses[0].T_map_lidar, T), kTolM);
    EXPECT_LT(rotationAngle(r.hypotheses[0].T_map_lidar, T) / kDeg, kTolDeg);
    // Assuming it level instead (a wrong IMU) must not give a confident answer as good.
    const auto level = gs.search(scan, Mat3d::Identity());
    EXPECT_TRUE(level.hypotheses.empty() || level.hypotheses[0].score < r.hypotheses[0].score);
}

TEST(GlobalSearch, TwoIdenticalHallsAreAmbiguousAndARegionPicksOne) {
    auto pts = lHall();
    const auto b = lHall(Vec3d(60, 0, 0));
    pts.insert(pts.end(), b.begin(), b.end());
    const auto m = makeMap(pts);
    GlobalSearch gs(m, GlobalSearchParams{});
    const SE3d T = makePoseRPY(63.2, 5.7, 1.4, 0, 0, 37 * kDeg);
    const auto scan = scanFrom(pts, T);
    const auto r = gs.search(scan, Mat3d::Identity());
    ASSERT_GE(r.hypotheses.size(), 2u);
    EXPECT_GE(r.runner_up_ratio, kAmbiguous);
    EXPECT_GT(r.runner_up_ratio, 0.95);
    // The two halls' copies of the pose are the first two.
    const double dx = std::abs(r.hypotheses[0].T_map_lidar.translation().x() -
                               r.hypotheses[1].T_map_lidar.translation().x());
    EXPECT_NEAR(dx, 60.0, 0.2);
    // Restricted to a disc around the true hall and +-30 deg: the truth only.
    SearchRegion reg;
    reg.centre = Vec3d(64, 5, 0);
    reg.radius = 6;
    reg.yaw = 30 * kDeg;
    reg.yaw_half_width = 30 * kDeg;
    const auto rr = gs.search(scan, Mat3d::Identity(), &reg);
    ASSERT_FALSE(rr.hypotheses.empty()) << rr.failure;
    EXPECT_LT(translationDistance(rr.hypotheses[0].T_map_lidar, T), kTolM);
    for (const auto& h : rr.hypotheses) {
        EXPECT_LT((h.T_map_lidar_search.translation() - reg.centre).head<2>().norm(), reg.radius + 1e-6);
        EXPECT_LT(std::abs(yawOf(h.T_map_lidar_search.linear()) - reg.yaw), reg.yaw_half_width + 1e-6);
    }
    EXPECT_LT(rr.yaws, r.yaws / 4);
    EXPECT_LT(rr.runner_up_ratio, kAmbiguous);
}

TEST(GlobalSearch, FeaturelessCorridorGivesNearEqualScoresAlongItsAxis) {
    const auto pts = corridor(200);
    const auto m = makeMap(pts);
    GlobalSearch gs(m, GlobalSearchParams{});
    const SE3d T = makePoseRPY(100.3, 1.4, 1.2, 0, 0, 3 * kDeg);
    const auto scan = scanFrom(pts, T);
    const auto r = gs.search(scan, Mat3d::Identity());
    ASSERT_GE(r.hypotheses.size(), 3u) << r.failure;
    EXPECT_GE(r.runner_up_ratio, kAmbiguous);
    double xmin = 1e9, xmax = -1e9;
    for (const auto& h : r.hypotheses) {
        EXPECT_GT(h.ratio_to_best, 0.95);
        // Across the corridor and in yaw (mod 180 deg) every hypothesis is right; along it, anywhere.
        EXPECT_NEAR(h.T_map_lidar.translation().y(), 1.4, 0.3);
        const double dyaw = std::remainder(yawOf(h.T_map_lidar.linear()) - 3 * kDeg, M_PI);
        EXPECT_LT(std::abs(dyaw) / kDeg, 3.0);
        xmin = std::min(xmin, h.T_map_lidar.translation().x());
        xmax = std::max(xmax, h.T_map_lidar.translation().x());
    }
    EXPECT_GE(xmax - xmin, 4.0) << "hypotheses spread along the corridor";
}

TEST(GlobalSearch, EmptyOrTooFewPointsGiveAnEmptyResult) {
    const auto pts = lHall();
    const auto m = makeMap(pts);
    GlobalSearch gs(m, GlobalSearchParams{});
    auto r = gs.search({}, std::nullopt);
    EXPECT_TRUE(r.hypotheses.empty());
    EXPECT_FALSE(r.failure.empty());
    r = gs.search({Vec3f(1, 2, 0), Vec3f(3, 1, 0.5), Vec3f(NAN, 0, 0)}, Mat3d::Identity());
    EXPECT_TRUE(r.hypotheses.empty());
    EXPECT_EQ(r.points_in, 2u);
    // Only ground points: nothing to score.
    std::vector<Vec3f> flat;
    for (int i = 0; i < 2000; ++i) flat.emplace_back(0.01f * (i % 50) - 5, 0.2f * (i / 50) - 4, -1.4f);
    r = gs.search(flat, Mat3d::Identity());
    EXPECT_TRUE(r.hypotheses.empty());
    // An empty map.
    const auto empty = makeMap({});
    GlobalSearch ge(empty, GlobalSearchParams{});
    r = ge.search(scanFrom(pts, makePoseRPY(3, 3, 1.4, 0, 0, 0)), std::nullopt);
    EXPECT_TRUE(r.hypotheses.empty());
    EXPECT_FALSE(r.failure.empty());
}
