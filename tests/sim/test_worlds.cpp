// The worlds are what doc/sim.md says: measured by casting rays from the platform's route.
#include <superloc/sim/raycaster.h>

#include "sim_test_utils.h"

using namespace superloc;
using namespace superloc::sim;

namespace {

// Horizontal free width across the path direction at a point (left + right ranges).
double widthAcross(const RayCaster& rc, const Vec3d& p, const Vec3d& dir) {
    const Vec3d lat = Vec3d(-dir.y(), dir.x(), 0).normalized();
    const RayHit l = rc.cast(p, lat, 0, 100), r = rc.cast(p, -lat, 0, 100);
    return (l.hit ? l.range : 100) + (r.hit ? r.range : 100);
}

}  // namespace

TEST(Worlds, CorridorIsLongNarrowAndFeatureless) {
    const SimConfig cfg = simtest::worldConfig("corridor");
    const SimScene sc = makeScene(cfg);
    const RayCaster rc(sc.world.mesh);
    const double L = cfg.ini.read_double("corridor", "length", 0);
    ASSERT_GE(L, 80.0);
    int recess_hits = 0, n = 0;
    for (double x = 5; x < L - 5; x += 0.25, ++n) {
        const double w = widthAcross(rc, {x, 0, 1.0}, Vec3d::UnitX());
        EXPECT_GE(w, 2.0);
        EXPECT_LE(w, 3.0 + 0.4);  // 2-3 m, a recess adds its depth
        if (w > 2.5 + 0.05) ++recess_hits;
    }
    EXPECT_GT(recess_hits, 0);
    EXPECT_LT(recess_hits, n / 10);  // recesses are a few percent of the length
    // Looking along the axis from the middle: nothing for tens of metres.
    const RayHit back = rc.cast({L / 2, 0, 1.0}, -Vec3d::UnitX(), 0, 500);
    ASSERT_TRUE(back.hit);
    EXPECT_NEAR(back.range, L / 2, 0.01);
    // The open area beyond the mouth: flat ground, nothing within 10 m of the mouth ahead.
    const RayHit ahead = rc.cast({L + 1, 0, 1.0}, Vec3d::UnitX(), 0, 10);
    EXPECT_FALSE(ahead.hit);
    EXPECT_NEAR(rc.cast({L + 10, 0, 1.0}, -Vec3d::UnitZ(), 0, 5).range, 1.0, 1e-4);
}

TEST(Worlds, CaveIsNarrowWindingAndSloping) {
    const SimScene sc = makeScene(simtest::worldConfig("cave"));
    const RayCaster rc(sc.world.mesh);
    double wmin = 1e9, wmax = 0, hmin = 1e9, hmax = -1e9, zmin = 1e9, zmax = -1e9, slope = 0;
    const auto& route = sc.world.route;
    for (size_t i = 1; i + 1 < route.size(); ++i) {
        const Vec3d d = route[i + 1].p - route[i - 1].p;
        const double w = widthAcross(rc, route[i].p, d);
        wmin = std::min(wmin, w), wmax = std::max(wmax, w);
        const double h = std::atan2(d.y(), d.x());
        hmin = std::min(hmin, h), hmax = std::max(hmax, h);
        zmin = std::min(zmin, route[i].p.z()), zmax = std::max(zmax, route[i].p.z());
        slope = std::max(slope, std::abs(std::atan2(d.z(), std::hypot(d.x(), d.y()))));
    }
    EXPECT_GE(wmin, 1.5);  // 2-5 m wide, walls roughened +-0.15 m (measured 1.3 m up)
    EXPECT_LE(wmin, 3.0);
    EXPECT_GE(wmax, 4.0);
    EXPECT_LE(wmax, 5.8);
    EXPECT_GT((hmax - hmin) * 180 / M_PI, 60.0);  // winding
    EXPECT_GT(zmax - zmin, 3.0);                  // sloping
    EXPECT_GT(slope * 180 / M_PI, 5.0);
}

TEST(Worlds, OpenfieldIsFlatWithFarObjects) {
    const SimScene sc = makeScene(simtest::worldConfig("openfield"));
    const RayCaster rc(sc.world.mesh);
    double nearest = 1e9;
    for (const auto& w : sc.world.route)
        for (int k = 0; k < 72; ++k) {
            const double a = k * M_PI / 36;
            const RayHit h =
                rc.cast(w.p + Vec3d(0, 0, 0.5), Vec3d(std::cos(a), std::sin(a), 0), 0, 200);
            if (h.hit) nearest = std::min(nearest, h.range);
            EXPECT_NEAR(rc.cast(w.p, -Vec3d::UnitZ(), 0, 5).range, 0.5, 0.1);  // flat ground
        }
    EXPECT_GT(nearest, 8.0);  // sparse, far objects only
}

TEST(Worlds, OfficeIsEnclosedEverywhere) {
    const SimScene sc = makeScene(simtest::worldConfig("office"));
    const RayCaster rc(sc.world.mesh);
    // Every horizontal ray from anywhere on the route hits something within 35 m.
    for (const auto& w : sc.world.route)
        for (int k = 0; k < 36; ++k) {
            const double a = k * M_PI / 18;
            EXPECT_TRUE(rc.cast(w.p, Vec3d(std::cos(a), std::sin(a), 0), 0, 35).hit);
        }
}
