// The registration voxel map: per-voxel statistics, O(1) lookup, levels, memory.
#include <gtest/gtest.h>
#include <superloc/map/prior_map.h>
#include <superloc/map/voxel_map.h>

#include <random>

using namespace superloc;
using namespace superloc::map;

namespace {
/// A tilted plane z = 0.1 x + 0.2 y + 3 sampled every 5 cm over 10 x 10 m, 1 cm noise.
std::vector<Vec3f> tiltedPlane() {
    std::mt19937 rng(3);
    std::normal_distribution<float> n(0, 0.01f);
    std::vector<Vec3f> pts;
    for (int i = 0; i < 200; ++i)
        for (int j = 0; j < 200; ++j) {
            const float x = -5 + 0.05f * i, y = -5 + 0.05f * j;
            pts.emplace_back(x, y, 0.1f * x + 0.2f * y + 3 + n(rng));
        }
    return pts;
}
}  // namespace

TEST(VoxelMap, PlaneStatisticsAtEveryLevel) {
    VoxelMap::Params p;
    p.finest = 0.5;
    p.levels = 3;
    const VoxelMap vm(tiltedPlane(), p);
    ASSERT_EQ(vm.levels(), 3);
    const Vec3f n_true = Vec3f(-0.1f, -0.2f, 1).normalized();
    for (int l = 0; l < 3; ++l) {
        EXPECT_DOUBLE_EQ(vm.levelSize(l), 0.5 * (1 << l));
        // A point on the plane finds its voxel; the voxel's plane passes through it.
        const Vec3f q(1.3f, -2.1f, 0.1f * 1.3f + 0.2f * -2.1f + 3);
        const VoxelStats* v = vm.find(l, q);
        ASSERT_NE(v, nullptr) << "level " << l;
        EXPECT_GT(std::abs(v->normal.dot(n_true)), 0.999f);
        EXPECT_LT(std::abs(v->normal.dot(q - v->mean)), 0.02f);
        EXPECT_NEAR(v->thickness, 0.01f, 0.004f);
        EXPECT_GT(v->planarity, 0.5f);
        // 2 m above the plane there is nothing at the finest level.
        if (l == 0) {
            EXPECT_EQ(vm.find(l, q + Vec3f(0, 0, 2)), nullptr);
        }
    }
    const auto info = vm.info();
    EXPECT_GT(info[0].voxels, info[1].voxels);
    EXPECT_GT(info[1].voxels, info[2].voxels);
    // Nothing per point is kept: a few bytes per input point.
    EXPECT_LT(static_cast<double>(vm.memoryBytes()) / 40000.0, 64.0);
}

TEST(VoxelMap, LineAndSparseVoxels) {
    std::vector<Vec3f> pole;
    for (int k = 0; k < 40; ++k) pole.emplace_back(0.2f, 0.2f, 0.01f + 0.0125f * k);  // 0.5 m of a vertical line
    pole.emplace_back(3.1f, 3.1f, 0.1f);  // a lone point: below min_points
    VoxelMap::Params p;
    p.levels = 1;
    const VoxelMap vm(pole, p);
    const VoxelStats* v = vm.find(0, Vec3f(0.25f, 0.25f, 0.25f));
    ASSERT_NE(v, nullptr);
    EXPECT_GT(v->linearity, 0.95f);
    EXPECT_GT(std::abs(v->direction.z()), 0.999f);
    EXPECT_EQ(vm.find(0, Vec3f(3.1f, 3.1f, 0.1f)), nullptr);
    EXPECT_EQ(vm.find(0, Vec3f(NAN, 0, 0)), nullptr);
    EXPECT_EQ(vm.find(0, Vec3f(1e30f, 0, 0)), nullptr);
}

TEST(VoxelMap, RejectsBadParameters) {
    VoxelMap::Params p;
    p.finest = 0;
    EXPECT_THROW(VoxelMap({}, p), std::invalid_argument);
    p = {};
    p.levels = 0;
    EXPECT_THROW(VoxelMap({}, p), std::invalid_argument);
    p = {};
    p.overlap = 0.5;
    EXPECT_THROW(VoxelMap({}, p), std::invalid_argument);
    MapParams mp;
    mp.reg_levels = 9;
    EXPECT_THROW(mp.validate(), std::exception);
}

TEST(VoxelMap, PriorMapBuildsItWithinSixtyFourBytesPerPoint) {
    PointCloud c;
    c.points = tiltedPlane();
    MapParams mp;
    mp.voxel_size = 0;
    const PriorMap m(c, mp);
    EXPECT_NE(m.voxels().find(0, Vec3f(0, 0, 3)), nullptr);
    EXPECT_GT(m.geometry(0).planarity, 0.5f);
    // Points, nearest-neighbour grid, per-point geometry and voxel map together (issue #10's
    // budget); a regression that kept a second copy of the points would exceed it.
    EXPECT_LE(m.memoryBytes(), 64 * m.size());
    EXPECT_GE(m.memoryBytes(), (sizeof(Vec3f) + sizeof(PointGeometry)) * m.size());
}
