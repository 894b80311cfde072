#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/features/classify.h>
#include <superloc/features/deskew.h>
#include <superloc/features/features_params.h>
#include <superloc/features/voxel_selector.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

using namespace superloc;
using namespace superloc::features;

TEST(Deskew, UndoesFastRotationAndTranslation) {
    // A sensor spinning at 3 rad/s (172 deg/s) in yaw, rolling a bit and driving 10 m/s during a
    // 0.1 s sweep; points are a box room seen from inside, measured at their own times.
    const Vec3d v(10, 0.5, 0), w(0.2, -0.1, 3.0);
    const double period = 0.1;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Vec3f> world_end, measured;
    std::vector<float> rel;
    const int n = 3000;
    for (int i = 0; i < n; ++i) {
        const double s = -period + period * i / (n - 1);  // firing order
        const double az = 2 * M_PI * i / n;
        const Vec3d dir(std::cos(az), std::sin(az), 0.3 * u(rng));
        const Vec3d P = dir.normalized() * (8 + 2 * u(rng));  // true point, end frame
        // Sensor pose at s relative to the end: T_end_s = (Exp(w s), v s); measured in frame s.
        const Mat3d R = expSO3(w * s);
        const Vec3d p = R.transpose() * (P - v * s);
        world_end.push_back(P.cast<float>());
        measured.push_back(p.cast<float>());
        rel.push_back(static_cast<float>(s));
    }
    std::vector<uint32_t> idx(n);
    for (int i = 0; i < n; ++i) idx[i] = i;
    std::vector<Vec3f> out;
    deskewPoints(measured, rel, idx, SweepMotion::fromTwist(v, w, period), out);
    double max_err = 0, max_raw = 0;
    for (int i = 0; i < n; ++i) {
        max_err = std::max(max_err, double((out[i] - world_end[i]).norm()));
        max_raw = std::max(max_raw, double((measured[i] - world_end[i]).norm()));
    }
    EXPECT_LT(max_err, 3e-3) << "deskewed";
    EXPECT_GT(max_raw, 1.0) << "the skew itself must be large for the test to mean anything";

    // No per-point time: points pass unchanged.
    deskewPoints(measured, {}, idx, SweepMotion::fromTwist(v, w, period), out);
    EXPECT_EQ(out[5], measured[5]);
}

TEST(VoxelSelector, OnePointPerVoxelInFiringOrder) {
    std::vector<Vec3f> pts = {{0.1f, 0.1f, 0.1f}, {0.2f, 0.2f, 0.2f}, {1.1f, 0.1f, 0.1f},
                              {-0.1f, 0.1f, 0.1f}, {0.3f, 0.1f, 0.4f}, {1.2f, 0.2f, 0.3f}};
    std::vector<uint32_t> all = {0, 1, 2, 3, 4, 5}, out;
    VoxelSelector sel;
    sel.select(pts, all, 0.5f, out);
    EXPECT_EQ(out, (std::vector<uint32_t>{0, 2, 3}));
    // Storage is reused: a second call gives the same answer.
    sel.select(pts, all, 0.5f, out);
    EXPECT_EQ(out, (std::vector<uint32_t>{0, 2, 3}));
    // Large random cloud: every kept point in a distinct voxel, every voxel represented.
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-20, 20);
    std::vector<Vec3f> big(50000);
    std::vector<uint32_t> idx(big.size());
    for (size_t i = 0; i < big.size(); ++i) big[i] = Vec3f(u(rng), u(rng), u(rng) * 0.1f), idx[i] = i;
    sel.select(big, idx, 2.0f, out);
    std::set<std::tuple<int, int, int>> cells, kept;
    for (const auto& p : big)
        cells.insert({int(std::floor(p.x() / 2)), int(std::floor(p.y() / 2)), int(std::floor(p.z() / 2))});
    for (uint32_t i : out)
        kept.insert({int(std::floor(big[i].x() / 2)), int(std::floor(big[i].y() / 2)),
                     int(std::floor(big[i].z() / 2))});
    EXPECT_EQ(kept.size(), out.size());
    EXPECT_EQ(kept, cells);
    // Tens of thousands of voxels (the table starts at 4096 slots and grows while it fills):
    // still the first point of every voxel, in order.
    const auto cell = [](const Vec3f& p, float v) {
        return std::tuple<int, int, int>{int(std::floor(p.x() / v)), int(std::floor(p.y() / v)),
                                         int(std::floor(p.z() / v))};
    };
    sel.select(big, idx, 0.25f, out);
    std::map<std::tuple<int, int, int>, uint32_t> first;
    for (uint32_t i = 0; i < big.size(); ++i) first.emplace(cell(big[i], 0.25f), i);
    ASSERT_GT(first.size(), 20000u);
    std::vector<uint32_t> expect;
    for (const auto& [c, i] : first) expect.push_back(i);
    std::sort(expect.begin(), expect.end());
    EXPECT_EQ(out, expect);
    // And the small case again in the grown table.
    sel.select(pts, all, 0.5f, out);
    EXPECT_EQ(out, (std::vector<uint32_t>{0, 2, 3}));
    // The one-pass range filter + selection: the points in range (NaN and far points out), and
    // of those what select() keeps.
    big[7] = Vec3f(NAN, 0, 0);
    big[8] = Vec3f(1e6f, 0, 0);
    std::vector<uint32_t> valid, valid1, out1;
    for (uint32_t i = 0; i < big.size(); ++i) {
        const float r = big[i].norm();
        if (r >= 1.0f && r <= 25.0f) valid.push_back(i);
    }
    sel.select(big, valid, 0.5f, out);
    VoxelSelector sel1;
    sel1.selectInRange(big, 1.0f, 25.0f, 0.5f, valid1, out1);
    EXPECT_LT(valid.size(), big.size() - 2);
    EXPECT_EQ(valid1, valid);
    EXPECT_EQ(out1, out);
}

// A scan as a LiDAR fires it: consecutive points a few cm apart, so most share the last point's
// voxel (the selection's shortcut skips their key), crossing negative coordinates and landing on
// voxel faces exactly (x = -0.5, 0, 0.5 ...). Against the rule written out: the first point of
// each voxel, in order.
TEST(VoxelSelector, FiringOrderedRunsKeepTheFirstPointOfEachVoxel) {
    std::vector<Vec3f> pts;
    // Runs along each axis in steps of 1/8 m (exact in binary): every second or fourth point lies
    // on a face of the voxel the point before it is in.
    for (int axis = 0; axis < 3; ++axis)
        for (int k = -16; k <= 16; ++k) {
            Vec3f p(2.1f, 2.1f, 0.1f);
            p[axis] = 0.125f * static_cast<float>(k) + (axis == 2 ? 0.0f : 2.0f);
            pts.push_back(p);
        }
    for (int ring = 0; ring < 16; ++ring)
        for (int k = 0; k < 2000; ++k) {
            const float a = static_cast<float>(k) * 0.00314f, r = 3.0f + 0.7f * static_cast<float>(ring);
            pts.emplace_back(r * std::cos(a), r * std::sin(a), -1.0f + 0.125f * static_cast<float>(ring));
            if (k % 97 == 0) pts.emplace_back(0.5f * static_cast<float>(k % 5) - 1.0f, -0.5f, 0.0f);  // on faces
        }
    for (const float voxel : {0.5f, 0.1f, 0.25f}) {
        std::map<std::tuple<int64_t, int64_t, int64_t>, uint32_t> first;
        std::vector<uint32_t> expect, valid_expect;
        for (uint32_t i = 0; i < pts.size(); ++i) {
            const float r = pts[i].norm();
            if (!(r >= 1.0f && r <= 12.0f)) continue;
            valid_expect.push_back(i);
            const float inv = 1.0f / voxel;
            const auto c = std::make_tuple(static_cast<int64_t>(std::floor(pts[i].x() * inv)),
                                           static_cast<int64_t>(std::floor(pts[i].y() * inv)),
                                           static_cast<int64_t>(std::floor(pts[i].z() * inv)));
            if (first.emplace(c, i).second) expect.push_back(i);
        }
        VoxelSelector sel;
        std::vector<uint32_t> valid, out;
        sel.selectInRange(pts, 1.0f, 12.0f, voxel, valid, out);
        EXPECT_EQ(valid, valid_expect) << voxel;
        EXPECT_EQ(out, expect) << voxel;
        sel.select(pts, valid, voxel, out);
        EXPECT_EQ(out, expect) << voxel;
        // A selector whose last cloud came in no firing order (its points seldom in their
        // predecessor's voxel) skips the shortcut on the next call: the same answer.
        std::vector<uint32_t> shuffled = valid, ignored;
        std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(3));
        VoxelSelector other;
        other.select(pts, shuffled, voxel, ignored);
        other.selectInRange(pts, 1.0f, 12.0f, voxel, valid, out);
        EXPECT_EQ(out, expect) << voxel << ", after a shuffled cloud";
    }
}

TEST(Preprocess, RangeFilterDropsNaNAndOutOfRange) {
    std::vector<Vec3f> pts = {{0.5f, 0, 0}, {5, 0, 0}, {NAN, 0, 0}, {200, 0, 0}, {0, 3, 4}};
    std::vector<uint32_t> out, selected;
    VoxelSelector sel;
    sel.selectInRange(pts, 1.0f, 100.0f, 0.5f, out, selected);
    EXPECT_EQ(out, (std::vector<uint32_t>{1, 4}));
    EXPECT_EQ(selected, (std::vector<uint32_t>{1, 4}));
    std::vector<uint32_t> idx(100), few;
    for (uint32_t i = 0; i < 100; ++i) idx[i] = i;
    takeEvenly(idx, 10, few);
    ASSERT_EQ(few.size(), 10u);
    EXPECT_EQ(few.front(), 0u);
    EXPECT_EQ(few[5], 50u);
    takeEvenly(idx, 1000, few);
    EXPECT_EQ(few.size(), 100u);
}

TEST(Classify, PlaneLinePoint) {
    // l1 : l2 : l3 = 1 : 0.9 : 0.01 -> planarity 0.89, linearity 0.1: a plane.
    EXPECT_EQ(classifyShape(0.89f, 0.1f, 0.1, 0.7), FeatureType::Plane);
    // An elongated but thin patch, 1 : 0.2 : 0.005, is still a plane (low planarity 0.195).
    EXPECT_EQ(classifyShape(0.195f, 0.8f, 0.1, 0.7), FeatureType::Plane);
    // 1 : 0.05 : 0.04 -> a line; 1 : 0.8 : 0.6 -> a blob (point).
    EXPECT_EQ(classifyShape(0.01f, 0.95f, 0.1, 0.7), FeatureType::Line);
    EXPECT_EQ(classifyShape(0.2f, 0.2f, 0.1, 0.7), FeatureType::Point);
    EXPECT_NEAR(shapeThickness(0.2f, 0.2f), 0.75f, 1e-6f);
}

TEST(FeaturesParams, RejectsBadValues) {
    mrpt::config::CConfigFileMemory bad("[features]\nvoxel_size = 0\n");
    EXPECT_THROW(loadParams<FeaturesParams>(bad, "features", "t.ini"), ConfigError);
    mrpt::config::CConfigFileMemory good("[features]\nvoxel_size = 0.8\nmax_features=500\n");
    const auto p = loadParams<FeaturesParams>(good, "features", "t.ini");
    EXPECT_DOUBLE_EQ(p.voxel_size, 0.8);
    EXPECT_EQ(p.max_features, 500);
}
