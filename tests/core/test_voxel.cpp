#include <gtest/gtest.h>
#include <superloc/core/voxel.h>

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
