#include <gtest/gtest.h>
#include <superloc/core/voxel.h>

#include <random>
#include <map>
#include <set>
#include <tuple>

using namespace superloc;

TEST(Voxel, OnePointPerOccupiedCellNearestCentroid) {
    PointCloud c;
    // Cell (0,0,0) with 3 points, centroid (0.2,0.2,0.2): the middle one is kept.
    c.points = {{0.05f, 0.05f, 0.05f}, {0.21f, 0.2f, 0.2f}, {0.34f, 0.35f, 0.35f},
                {1.5f, 0.2f, 0.2f},  // cell (3,0,0)
                {-0.1f, 0.1f, 0.1f}};  // cell (-1,0,0): floor, not truncation
    c.intensity = {1, 2, 3, 4, 5};
    const PointCloud d = voxelDownsample(c, 0.5f);
    ASSERT_EQ(d.size(), 3u);
    EXPECT_FLOAT_EQ(d.intensity[0], 2);
    EXPECT_FLOAT_EQ(d.intensity[1], 4);
    EXPECT_FLOAT_EQ(d.intensity[2], 5);
    EXPECT_EQ(voxelDownsample(c, 0.f).size(), 5u);
}

// Issue 36: a voxel far below the points' spacing keeps every point. With 32-bit indices,
// floor(10 m / 1e-9 m) overflowed and distant points shared a voxel.
TEST(Voxel, TinyVoxelKeepsDistantPointsApart) {
    PointCloud c;
    c.points = {{10.f, 0.f, 0.f}, {20.f, 0.f, 0.f}, {-30.f, 5.f, 1.f}, {10.f, 0.5f, 0.f}};
    EXPECT_EQ(voxelDownsample(c, 1e-9f).size(), 4u);
    const VoxelKey a = voxelKey(c.points[0], 1e-9f), b = voxelKey(c.points[1], 1e-9f);
    EXPECT_FALSE(a == b);
    EXPECT_GT(a.x, int64_t{1} << 33);
    // The keys of ordinary voxels are what they were.
    EXPECT_EQ(voxelKey({-0.1f, 0.7f, 2.5f}, 0.5f).x, -1);
    EXPECT_EQ(voxelKey({-0.1f, 0.7f, 2.5f}, 0.5f).y, 1);
    EXPECT_EQ(voxelKey({-0.1f, 0.7f, 2.5f}, 0.5f).z, 5);
}

TEST(Voxel, AnIndexBeyond62BitsIsAnErrorNamingTheVoxel) {
    PointCloud c;
    c.points = {{1e7f, 0.f, 0.f}, {0.f, 0.f, 0.f}};
    try {
        voxelDownsample(c, 1e-15f);
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("voxel size 1e-15 m is too small"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
}

// voxelDownsampleIndices against the rule written out with an ordered map: per voxel (in order
// of first occurrence) the point nearest its centroid, the first of equally near ones. Clouds
// with negative coordinates, duplicate points (ties), and voxels whose indices do not pack into
// VoxelIndex's flat table (a 1e-6 m voxel at 10 km: its far map).
TEST(Voxel, DownsampleIndicesIsTheRuleWrittenOut) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> U(-3.f, 3.f), F(-2e4f, 2e4f);
    for (int trial = 0; trial < 4; ++trial) {
        const bool far = trial == 3;
        const float voxel = far ? 1e-6f : (trial == 0 ? 0.5f : trial == 1 ? 0.1f : 1.3f);
        std::vector<Vec3f> pts;
        for (int i = 0; i < 20000; ++i) {
            pts.push_back(far ? Vec3f(F(rng), F(rng), U(rng)) : Vec3f(U(rng), U(rng), U(rng)));
            if (i % 7 == 0) pts.push_back(pts.back());  // an exact tie
        }
        std::map<std::tuple<int64_t, int64_t, int64_t>, size_t> rank;
        std::vector<Eigen::Vector3d> sum;
        std::vector<uint32_t> n;
        std::vector<size_t> cell(pts.size());
        for (size_t i = 0; i < pts.size(); ++i) {
            const VoxelKey k = voxelKey(pts[i], voxel);
            const auto [it, fresh] = rank.try_emplace({k.x, k.y, k.z}, sum.size());
            if (fresh) sum.emplace_back(Eigen::Vector3d::Zero()), n.push_back(0);
            sum[it->second] += pts[i].cast<double>();
            ++n[it->second];
            cell[i] = it->second;
        }
        std::vector<uint32_t> expect(sum.size(), UINT32_MAX);
        std::vector<float> best(sum.size());
        for (size_t i = 0; i < pts.size(); ++i) {
            const Vec3f centroid = (sum[cell[i]] / n[cell[i]]).cast<float>();
            const float d = (pts[i] - centroid).squaredNorm();
            if (expect[cell[i]] == UINT32_MAX || d < best[cell[i]]) expect[cell[i]] = static_cast<uint32_t>(i), best[cell[i]] = d;
        }
        EXPECT_EQ(voxelDownsampleIndices(pts, voxel), expect) << "voxel " << voxel;
    }
}

// VoxelSet answers as a std::set of the keys would, for negative, block-crossing and huge indices.
TEST(Voxel, VoxelSetMatchesAnOrderedSet) {
    std::mt19937_64 rng(9);
    std::uniform_int_distribution<int64_t> small(-40, 40), huge(-(int64_t{1} << 61), int64_t{1} << 61);
    std::set<std::tuple<int64_t, int64_t, int64_t>> ref;
    VoxelSet set;
    for (int i = 0; i < 200000; ++i) {
        const bool far = i % 50 == 0;
        const VoxelKey k{far ? huge(rng) : small(rng), small(rng), far ? huge(rng) : small(rng)};
        const bool fresh = ref.insert({k.x, k.y, k.z}).second;
        ASSERT_EQ(set.insert(k), fresh) << k.x << " " << k.y << " " << k.z;
    }
    EXPECT_EQ(set.size(), ref.size());
    EXPECT_GT(set.memoryBytes(), 0u);
}

// VoxelIndex keeps the first value of every key, as std::map::try_emplace does, for packed and
// far (beyond +-2^20) indices alike.
TEST(Voxel, VoxelIndexMatchesAnOrderedMap) {
    std::mt19937_64 rng(4);
    std::uniform_int_distribution<int64_t> small(-60, 60), edge(-(int64_t{1} << 20) - 2, -(int64_t{1} << 20) + 2),
        huge(-(int64_t{1} << 61), int64_t{1} << 61);
    std::map<std::tuple<int64_t, int64_t, int64_t>, uint32_t> ref;
    VoxelIndex index;
    for (uint32_t i = 0; i < 200000; ++i) {
        const int kind = i % 97 == 0 ? 2 : i % 89 == 0 ? 1 : 0;
        const int64_t a = kind == 2 ? huge(rng) : kind == 1 ? edge(rng) : small(rng);
        const VoxelKey k{a, small(rng), small(rng)};
        const auto [it, fresh] = ref.try_emplace({k.x, k.y, k.z}, i);
        const auto [value, inserted] = index.tryEmplace(k, i);
        ASSERT_EQ(inserted, fresh) << k.x << " " << k.y << " " << k.z;
        ASSERT_EQ(value, it->second);
    }
    EXPECT_EQ(index.size(), ref.size());
    EXPECT_GT(index.memoryBytes(), 0u);
}

// VoxelFirstPoints numbers the voxels by first occurrence and keeps each one's first point, as a
// std::map from the keys would, for points on voxel faces, negative coordinates and far points
// (keys beyond VoxelIndex's packed range); a point not finite throws naming the voxel size.
TEST(Voxel, VoxelFirstPointsMatchesAnOrderedMap) {
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<float> near(-3.0f, 3.0f), far(-4.0e5f, 4.0e5f);
    std::uniform_int_distribution<int> face(-60, 60);
    const float voxel = 0.05f;
    std::map<std::tuple<int64_t, int64_t, int64_t>, uint32_t> ref;
    std::vector<Vec3f> firsts;
    VoxelFirstPoints index(voxel);
    for (int i = 0; i < 200000; ++i) {
        Vec3f p(near(rng), near(rng), near(rng));
        if (i % 7 == 0) p.x() = static_cast<float>(face(rng)) * voxel;  // on a face
        if (i % 101 == 0) p.y() = far(rng);
        const VoxelKey k = voxelKey(p, voxel);
        const auto [it, fresh] = ref.try_emplace({k.x, k.y, k.z}, static_cast<uint32_t>(ref.size()));
        if (fresh) firsts.push_back(p);
        const auto [number, added] = index.add(p);
        ASSERT_EQ(added, fresh) << p.transpose();
        ASSERT_EQ(number, it->second) << p.transpose();
    }
    EXPECT_EQ(index.points(), firsts);
    EXPECT_EQ(index.size(), ref.size());
    // Slots of 4 bytes at a load of at most one half, and the points.
    EXPECT_LE(index.memoryBytes(), ref.size() * (16 + 2 * sizeof(Vec3f)) + 4 * 64);
    EXPECT_THROW(index.add(Vec3f(std::nanf(""), 0, 0)), std::invalid_argument);
    EXPECT_THROW(VoxelFirstPoints(0.0f), std::invalid_argument);
}
