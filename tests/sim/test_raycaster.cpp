#include <gtest/gtest.h>
#include <superloc/sim/raycaster.h>

using namespace superloc;
using namespace superloc::sim;

TEST(RayCaster, RangesInsideABoxRoomAreExact) {
    Mesh m;
    m.addBox({-2, -3, 0}, {4, 5, 2.5});
    RayCaster rc(m);
    const Vec3d o(0, 0, 1);
    const auto hx = rc.cast(o, Vec3d::UnitX(), 0, 100);
    ASSERT_TRUE(hx.hit);
    EXPECT_NEAR(hx.range, 4.0, 1e-5);
    EXPECT_NEAR(std::abs(hx.normal.x()), 1.0, 1e-9);
    const auto hz = rc.cast(o, -Vec3d::UnitZ(), 0, 100);
    ASSERT_TRUE(hz.hit);
    EXPECT_NEAR(hz.range, 1.0, 1e-5);
    EXPECT_FALSE(rc.cast(o, Vec3d::UnitX(), 0, 3.5).hit);  // beyond t_max

    // The packet path gives the same answers as single rays.
    std::vector<Vec3d> dirs;
    for (int k = 0; k < 37; ++k) {
        const double a = 0.17 * k;
        dirs.push_back(Vec3d(std::cos(a), std::sin(a), 0.3 * std::sin(3 * a)).normalized());
    }
    std::vector<RayHit> fan;
    rc.castFan(o, dirs, 0, 100, fan);
    ASSERT_EQ(fan.size(), dirs.size());
    for (size_t k = 0; k < dirs.size(); ++k) {
        const auto h = rc.cast(o, dirs[k], 0, 100);
        ASSERT_TRUE(fan[k].hit);
        EXPECT_NEAR(fan[k].range, h.range, 1e-5);
        EXPECT_EQ(fan[k].triangle, h.triangle);
    }
}

TEST(RayCaster, EmptyMeshIsAnError) { EXPECT_THROW(RayCaster{Mesh{}}, std::runtime_error); }
