#include <gtest/gtest.h>
#include <superloc/eval/map_metrics.h>

#include <stdexcept>

using namespace superloc;
using namespace superloc::eval;

namespace {
/// 100 x 100 points on z = z0, 2 cm apart, at 0.005 + 0.02 i (never on a 5 cm voxel border).
PointCloud grid(float z0) {
    PointCloud c;
    for (int i = 0; i < 100; ++i)
        for (int j = 0; j < 100; ++j)
            c.points.emplace_back(0.005f + 0.02f * i, 0.005f + 0.02f * j, z0);
    return c;
}
}  // namespace

TEST(MapMetrics, IdenticalMapsHaveNoOutliers) {
    const MapResult r = computeMapOutliers(grid(0), grid(0), 0.05, 0.10);
    // 100 points over [0.005, 1.985] fall in 40 voxels of 5 cm per axis: 40 x 40.
    EXPECT_EQ(r.points, 1600u);
    EXPECT_EQ(r.gt_points, 10000u);
    EXPECT_DOUBLE_EQ(r.outlier_percent, 0.0);
    EXPECT_DOUBLE_EQ(r.median_dist, 0.0);
}

// Every point 0.2 m above the GT plane: the nearest GT point is straight below it, 0.2 m away.
TEST(MapMetrics, MapShiftedBy20cmIsAllOutliers) {
    const MapResult r = computeMapOutliers(grid(0.2f), grid(0), 0.05, 0.10);
    EXPECT_DOUBLE_EQ(r.outlier_percent, 100.0);
    EXPECT_NEAR(r.median_dist, 0.2, 1e-6);
    EXPECT_NEAR(r.mean_dist, 0.2, 1e-6);
}

// 5 cm is within the 10 cm threshold; with a 4 cm threshold it is not.
TEST(MapMetrics, ThresholdDecides) {
    EXPECT_DOUBLE_EQ(computeMapOutliers(grid(0.05f), grid(0), 0.05, 0.10).outlier_percent, 0.0);
    EXPECT_DOUBLE_EQ(computeMapOutliers(grid(0.05f), grid(0), 0.05, 0.04).outlier_percent, 100.0);
    // Half of the points moved up by 0.3 m: 50 %.
    PointCloud half = grid(0);
    for (size_t i = 0; i < half.points.size(); ++i)
        if (half.points[i].x() < 1.0f) half.points[i].z() = 0.3f;
    const MapResult r = computeMapOutliers(half, grid(0), 0.0, 0.10);
    EXPECT_DOUBLE_EQ(r.outlier_percent, 50.0);
    EXPECT_NEAR(r.median_dist, 0.15, 1e-6);  // even count: mean of 0 and 0.3
}

TEST(MapMetrics, EmptyMapsAreErrors) {
    EXPECT_THROW(computeMapOutliers(PointCloud{}, grid(0), 0.05, 0.1), std::invalid_argument);
    EXPECT_THROW(computeMapOutliers(grid(0), PointCloud{}, 0.05, 0.1), std::invalid_argument);
}
