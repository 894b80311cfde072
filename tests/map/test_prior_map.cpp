// PriorMap: normals of synthetic surfaces, orientation, nearest-neighbour queries, edge cases.
#include <superloc/core/se3.h>
#include <superloc/map/prior_map.h>
#include <superloc_testing/testing.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <thread>

using namespace superloc;
using namespace superloc::map;

namespace {


double angleBetweenLines(const Vec3f& a, const Vec3f& b) {
    const double c = std::abs(a.cast<double>().normalized().dot(b.cast<double>().normalized()));
    return std::acos(std::min(1.0, c));
}

/// A 4 m x 4 m grid (2 cm spacing) on the plane through `origin` spanned by u, v.
PointCloud planeCloud(const Vec3f& origin, const Vec3f& u, const Vec3f& v, float noise = 0) {
    std::mt19937 rng(7);
    std::normal_distribution<float> gauss(0.f, 1.f);
    const Vec3f n = u.cross(v).normalized();
    PointCloud c;
    for (int i = 0; i < 200; ++i)
        for (int j = 0; j < 200; ++j)
            c.points.push_back(
                origin + (i * 0.02f - 2.f) * u.normalized() + (j * 0.02f - 2.f) * v.normalized() +
                noise * gauss(rng) * n);
    return c;
}

/// A vertical cylinder of radius r around the z axis, 2 cm spacing.
PointCloud cylinderCloud(float r) {
    PointCloud c;
    const int around = static_cast<int>(2 * M_PI * r / 0.02);
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < 100; ++j) {
            const float a = static_cast<float>(2 * M_PI * i / around);
            c.points.emplace_back(r * std::cos(a), r * std::sin(a), j * 0.02f);
        }
    return c;
}

MapParams params(double voxel = 0.0, int k = 10) {
    MapParams p;
    p.geometry_at_load = false;  // each point's geometry by its first query: what these tests check
    p.voxel_size = voxel;
    p.normal_k = k;
    p.normal_max_radius = 0.5;
    return p;
}

}  // namespace

TEST(FitNeighborhood, TiltedPlaneGivesItsNormal) {
    const Vec3f n = Vec3f(0.3f, -0.2f, 0.9f).normalized();
    const Vec3f u = n.unitOrthogonal(), v = n.cross(u);
    std::vector<Vec3f> pts;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) pts.push_back(Vec3f(1, 2, 3) + 0.1f * i * u + 0.07f * j * v);
    const PointGeometry g = fitNeighborhood(pts);
    EXPECT_LT(angleBetweenLines(g.normal, n), 1e-3);
    EXPECT_NEAR(g.normal.norm(), 1.0, 1e-5);
    EXPECT_GT(g.planarity, 0.3);
    EXPECT_LT(g.fit_residual, 1e-4);
}

TEST(FitNeighborhood, LineIsLinearAndTooFewPointsHaveNoGeometry) {
    std::vector<Vec3f> line;
    for (int i = 0; i < 10; ++i) line.emplace_back(0.1f * i, 0.f, 0.f);
    const PointGeometry g = fitNeighborhood(line);
    EXPECT_GT(g.linearity, 0.99);
    EXPECT_LT(g.planarity, 0.01);

    const PointGeometry none = fitNeighborhood({Vec3f(0, 0, 0), Vec3f(1, 0, 0)});
    EXPECT_EQ(none.normal.squaredNorm(), 0.f);
    EXPECT_TRUE(std::isinf(none.fit_residual));
    const PointGeometry same = fitNeighborhood({Vec3f(1, 1, 1), Vec3f(1, 1, 1), Vec3f(1, 1, 1)});
    EXPECT_EQ(same.normal.squaredNorm(), 0.f);
}

TEST(PriorMap, PlaneNormalsWithinOneDegree) {
    const Vec3f u(1, 0, 0.2f), v(0, 1, -0.1f);
    const Vec3f n = u.cross(v).normalized();
    const PriorMap map(planeCloud(Vec3f(0, 0, 1), u, v), params());
    ASSERT_EQ(map.size(), 40000u);
    for (size_t i = 0; i < map.size(); ++i) {
        ASSERT_LT(angleBetweenLines(map.geometry(i).normal, n), 1.0 * kDeg) << "point " << i;
        // Planarity is high inside; at the grid's border the neighbourhood is one-sided
        // (2 rows x 5 points), which reads as elongated.
        const Vec3f d = map.point(i) - Vec3f(0, 0, 1);
        if (std::abs(d.x()) < 1.8f && std::abs(d.y()) < 1.8f) {
            ASSERT_GT(map.geometry(i).planarity, 0.5) << "point " << i;
        }
        ASSERT_FALSE(map.geometry(i).oriented);
    }
}

TEST(PriorMap, CylinderNormalsAreRadialWithinOneDegree) {
    const PriorMap map(cylinderCloud(1.0f), params());
    ASSERT_GT(map.size(), 30000u);
    for (size_t i = 0; i < map.size(); ++i) {
        const Vec3f& p = map.point(i);
        const Vec3f radial(p.x(), p.y(), 0.f);
        ASSERT_LT(angleBetweenLines(map.geometry(i).normal, radial), 1.0 * kDeg) << "point " << i;
    }
}

TEST(PriorMap, NormalsFlipTowardTheViewpoint) {
    const PriorMap map(cylinderCloud(1.0f), params(), Vec3f(0, 0, 1));  // inside the cylinder
    for (size_t i = 0; i < map.size(); ++i) {
        const auto& g = map.geometry(i);
        ASSERT_TRUE(g.oriented);
        ASSERT_GT(g.normal.dot(Vec3f(0, 0, 1) - map.point(i)), 0.f) << "point " << i;
    }
}

TEST(PriorMap, NormalsFollowTheFilesNormalsWhenNoViewpoint) {
    PointCloud c = planeCloud(Vec3f::Zero(), Vec3f::UnitX(), Vec3f::UnitY());
    c.normals.assign(c.size(), Vec3f(0.1f, 0.f, -1.f));
    const PriorMap map(c, params());
    for (size_t i = 0; i < map.size(); i += 97) {
        EXPECT_TRUE(map.geometry(i).oriented);
        EXPECT_LT(map.geometry(i).normal.z(), -0.999f);
    }
}

TEST(PriorMap, FitResidualMeasuresSurfaceNoise) {
    const float sigma = 0.01f;
    const PriorMap map(
        planeCloud(Vec3f::Zero(), Vec3f::UnitX(), Vec3f::UnitY(), sigma), params(0.0, 20));
    std::vector<float> res;
    for (size_t i = 0; i < map.size(); ++i) res.push_back(map.geometry(i).fit_residual);
    std::nth_element(res.begin(), res.begin() + res.size() / 2, res.end());
    // The best-fit plane of 20 neighbours absorbs a little of the noise: RMS ~ 0.9 sigma.
    EXPECT_GT(res[res.size() / 2], 0.6 * sigma);
    EXPECT_LT(res[res.size() / 2], 1.2 * sigma);
}

TEST(PriorMap, VoxelFilterBoundsThePointDensity) {
    const PriorMap map(planeCloud(Vec3f::Zero(), Vec3f::UnitX(), Vec3f::UnitY()), params(0.1));
    // 4 m x 4 m at 0.1 m: 40 x 40 voxels (+1 row/column at the borders).
    EXPECT_GE(map.size(), 1600u);
    EXPECT_LE(map.size(), 41u * 41u);
}

TEST(PriorMap, KnnMatchesBruteForce) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> U(-5.f, 5.f);
    PointCloud c;
    for (int i = 0; i < 5000; ++i) c.points.emplace_back(U(rng), U(rng), U(rng));
    const PriorMap map(c, params());
    Neighbors nb;
    for (int q = 0; q < 50; ++q) {
        const Vec3f query(U(rng), U(rng), U(rng));
        std::vector<float> d2;
        for (const auto& p : map.points()) d2.push_back((p - query).squaredNorm());
        std::vector<float> sorted = d2;
        std::sort(sorted.begin(), sorted.end());
        map.knn(query, 8, nb);
        ASSERT_EQ(nb.indices.size(), 8u);
        for (size_t j = 0; j < 8; ++j) {
            EXPECT_FLOAT_EQ(nb.sq_dists[j], sorted[j]);
            EXPECT_FLOAT_EQ(d2[nb.indices[j]], sorted[j]);
        }
        const auto [idx, dist] = map.nearest(query);
        EXPECT_FLOAT_EQ(dist, sorted[0]);
        EXPECT_FLOAT_EQ(d2[idx], sorted[0]);
    }
}

TEST(PriorMap, GeometryIsComputedPerPointOnFirstUseAndMatchesBruteForce) {
    // Each point's geometry is computed by its first query, from its normal_k nearest points
    // within normal_max_radius: the same as a brute-force PCA of those points.
    const MapParams p = params(0.02, 10);
    const PriorMap map(cylinderCloud(2.0f), p);
    std::mt19937 rng(5);
    std::uniform_int_distribution<size_t> pick(0, map.size() - 1);
    for (int t = 0; t < 30; ++t) {
        const size_t i = pick(rng);
        std::vector<std::pair<float, size_t>> d;
        for (size_t j = 0; j < map.size(); ++j) d.emplace_back((map.point(j) - map.point(i)).squaredNorm(), j);
        std::partial_sort(d.begin(), d.begin() + 10, d.end());
        std::vector<Vec3f> nb;
        for (size_t j = 0; j < 10; ++j)
            if (d[j].first <= p.normal_max_radius * p.normal_max_radius) nb.push_back(map.point(d[j].second));
        const PointGeometry want = fitNeighborhood(nb);
        const PointGeometry& got = map.geometry(i);
        EXPECT_NEAR(std::abs(got.normal.dot(want.normal)), 1.0f, 1e-4f) << "point " << i;
        EXPECT_NEAR(got.planarity, want.planarity, 1e-4f);
        EXPECT_NEAR(got.fit_residual, want.fit_residual, 1e-5f);
    }
    EXPECT_THROW(map.geometry(map.size()), std::out_of_range);
}

TEST(PriorMap, ConcurrentGeometryQueriesAgree) {
    // Two threads ask for the same points' geometry at once (each point computed once, the other
    // thread waits for it): both see the single-threaded answer.
    const PriorMap a(cylinderCloud(2.0f), params(0.05));
    const PriorMap b(cylinderCloud(2.0f), params(0.05));
    std::vector<float> ga(a.size()), gb(a.size());
    const auto run = [&](std::vector<float>& out) {
        for (size_t i = 0; i < out.size(); ++i) out[i] = a.geometry(i).normal.x() + a.geometry(i).planarity;
    };
    std::thread t1(run, std::ref(ga)), t2(run, std::ref(gb));
    t1.join();
    t2.join();
    EXPECT_EQ(ga, gb);
    for (size_t i = 0; i < b.size(); ++i) ASSERT_EQ(b.geometry(i).normal.x() + b.geometry(i).planarity, ga[i]);
}

TEST(PriorMap, ConcurrentQueriesAgree) {
    const PriorMap map(cylinderCloud(2.0f), params(0.05));
    std::vector<uint32_t> a(2000), b(2000);
    const auto run = [&](std::vector<uint32_t>& out) {
        Neighbors nb;
        for (size_t i = 0; i < out.size(); ++i) {
            map.knn(Vec3f(0.001f * i, 1.5f, 0.5f), 5, nb);
            out[i] = nb.indices.back();
        }
    };
    std::thread t1(run, std::ref(a)), t2(run, std::ref(b));
    t1.join();
    t2.join();
    EXPECT_EQ(a, b);
}

TEST(PriorMap, SmallAndEmptyMaps) {
    PointCloud two;
    two.points = {Vec3f(0, 0, 0), Vec3f(1, 0, 0)};
    const PriorMap small(two, params());
    Neighbors nb;
    small.knn(Vec3f(0.9f, 0, 0), 10, nb);
    ASSERT_EQ(nb.indices.size(), 2u);
    EXPECT_EQ(nb.indices[0], 1u);
    EXPECT_TRUE(std::isinf(small.geometry(0).fit_residual));

    const PriorMap empty(PointCloud{}, params());
    EXPECT_EQ(empty.size(), 0u);
    empty.knn(Vec3f::Zero(), 3, nb);
    EXPECT_TRUE(nb.indices.empty());
    EXPECT_TRUE(std::isinf(empty.nearest(Vec3f::Zero()).second));
}

TEST(PriorMap, MovedMapKeepsWorking) {
    PriorMap a(cylinderCloud(1.0f), params(0.05));
    const size_t n = a.size();
    PriorMap b = std::move(a);
    ASSERT_EQ(b.size(), n);
    const auto [idx, d2] = b.nearest(b.point(10));
    EXPECT_EQ(d2, 0.f);
    EXPECT_EQ(b.point(idx), b.point(10));
}

TEST(PriorMap, NonFinitePointsAreDropped) {
    PointCloud c = cylinderCloud(1.0f);
    const size_t n = c.size();
    c.points[5] = Vec3f(NAN, 0, 0);
    c.points[9] = Vec3f(0, INFINITY, 0);
    const PriorMap map(c, params());
    EXPECT_EQ(map.size(), n - 2);
    for (const auto& p : map.points()) ASSERT_TRUE(p.allFinite());
}

TEST(PriorMap, GeometryPreparedAtLoadIsTheFirstUsesGeometryBitForBit) {
    // [map] geometry_at_load: every point's geometry computed up front on several threads (blocks
    // of 4096 points from a shared counter) is what the first query of each point computes.
    const PriorMap lazy(cylinderCloud(2.0f), params(0.01));
    const PriorMap ready(cylinderCloud(2.0f), params(0.01));
    ASSERT_GT(lazy.size(), 3u * 4096u) << "too few points for the helper threads to get a block";
    EXPECT_GE(ready.prepareGeometry(3), 0.0);
    for (size_t i = 0; i < lazy.size(); ++i) {
        const PointGeometry &a = lazy.geometry(i), &b = ready.geometry(i);
        ASSERT_EQ(a.normal, b.normal) << "point " << i;
        ASSERT_EQ(a.planarity, b.planarity) << "point " << i;
        ASSERT_EQ(a.linearity, b.linearity) << "point " << i;
        ASSERT_EQ(a.fit_residual, b.fit_residual) << "point " << i;
        ASSERT_EQ(a.oriented, b.oriented) << "point " << i;
    }
    // Prepared twice: nothing left to compute, nothing changed.
    EXPECT_GE(ready.prepareGeometry(2), 0.0);
    EXPECT_EQ(ready.geometry(7).normal, lazy.geometry(7).normal);
}

TEST(PriorMap, GeometryAtLoadIsPreparedByTheConstructorWithTheViewpointsOrientation) {
    // [map] geometry_at_load = true: the constructor builds the kd-tree and every point's geometry
    // (its memory counts them before any query), oriented toward the viewpoint as a first query's.
    MapParams at_load = params(0.02);
    at_load.geometry_at_load = true;
    const Vec3f viewpoint(0.0f, 0.0f, 1.0f);
    const PriorMap lazy(cylinderCloud(2.0f), params(0.02), viewpoint);
    const size_t lazy_bytes = lazy.memoryBytes();
    const PriorMap ready(cylinderCloud(2.0f), at_load, viewpoint);
    EXPECT_GT(ready.memoryBytes(), lazy_bytes + ready.size() * sizeof(PointGeometry) / 2)
        << "the kd-tree and the geometry should exist before any query";
    for (size_t i = 0; i < lazy.size(); ++i) {
        ASSERT_EQ(ready.geometry(i).normal, lazy.geometry(i).normal) << "point " << i;
        ASSERT_TRUE(ready.geometry(i).oriented) << "point " << i;
    }
    EXPECT_EQ(ready.memoryBytes(), lazy.memoryBytes());
}
