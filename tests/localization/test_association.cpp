// Association with a PriorMap (plane / line / point by the map's local shape) and the
// frames.csv writer's shape.
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/localization/association.h>
#include <superloc/app/run_outputs.h>

#include <random>
#include <sstream>

using namespace superloc;
using namespace superloc::localization;
using namespace superloc::app;

namespace {
// A floor (z = 0, 10 x 10 m, 5 cm grid) and a thin vertical pole at (3, 3).
PointCloud floorAndPole() {
    PointCloud c;
    for (int i = 0; i < 200; ++i)
        for (int j = 0; j < 200; ++j) c.points.emplace_back(-5.0f + 0.05f * i, -5.0f + 0.05f * j, 0.0f);
    for (int k = 0; k < 100; ++k) c.points.emplace_back(3.0f, 3.0f, 1.0f + 0.05f * k);
    return c;
}
}  // namespace

TEST(Association, FloorIsPlanePoleIsLine) {
    map::MapParams mp;
    mp.voxel_size = 0;
    const map::PriorMap m(floorAndPole(), mp, Vec3f(0, 0, 1.5f));
    const SE3d T = makePoseRPY(0.02, -0.01, 1.5, 0, 0, 0.3);  // body 1.5 m above the floor
    // Features: floor points and pole points seen from T, 3 cm off their surfaces.
    std::vector<Vec3d> pts;
    for (int i = 0; i < 50; ++i) pts.push_back(T.inverse() * Vec3d(-3 + 0.1 * i, 1.0, 0.03));
    for (int k = 0; k < 20; ++k) pts.push_back(T.inverse() * Vec3d(3.03, 3.0, 1.5 + 0.1 * k));
    pts.push_back(T.inverse() * Vec3d(0, 0, 30));  // nothing near: too far
    AssociationParams ap;
    std::vector<Correspondence> corr;
    AssociationStats st;
    std::vector<uint32_t> feature_of;
    associate(pts, T, m, ap, corr, st, &feature_of);
    EXPECT_EQ(st.too_far, 1u);
    EXPECT_EQ(st.plane, 50u);
    EXPECT_EQ(st.line, 20u);
    ASSERT_EQ(feature_of.size(), corr.size());
    for (const auto& c : corr) {
        if (c.type == FeatureType::Plane) {
            EXPECT_NEAR(std::abs(c.n.z()), 1.0, 1e-3);
            EXPECT_NEAR(fusion::correspondenceError(c, T), 0.03, 1e-3);  // point-to-plane
        } else {
            EXPECT_NEAR(std::abs(c.n.z()), 1.0, 1e-3);                   // line direction
            EXPECT_NEAR(fusion::correspondenceError(c, T), 0.03, 2e-3);  // point-to-line
        }
        EXPECT_GT(c.weight, 0.5);
    }
    // All within 5 cm: every associated feature is an inlier; 70 of the 71 features.
    const InlierStats in = inlierStats(corr, pts.size(), T, 0.05);
    EXPECT_EQ(in.inliers, 70u);
    EXPECT_NEAR(in.ratio, 70.0 / 71.0, 1e-12);
    EXPECT_NEAR(in.rms, 0.03, 2e-3);
    // Moved 20 cm up, the floor features are no longer inliers at 5 cm.
    const SE3d T_up = makePoseRPY(0.02, -0.01, 1.7, 0, 0, 0.3);
    EXPECT_LT(inlierStats(corr, pts.size(), T_up, 0.05).inliers, 25u);
}

TEST(RunOutputs, CsvLineMatchesHeader) {
    FrameReport r;
    r.t = 12.5;
    r.degenerate_axes = "xyaw";
    r.diverged_reason = "jump";
    const std::string line = framesCsvLine(r, makePoseRPY(1, 2, 3, 0, 0, 0.5));
    const auto count = [](const std::string& s) { return std::count(s.begin(), s.end(), ','); };
    EXPECT_EQ(count(line), count(framesCsvHeader()));
    EXPECT_EQ(line.rfind("12.500000000,1.000000,2.000000,3.000000,", 0), 0u) << line;
    EXPECT_NE(line.find(",xyaw,"), std::string::npos);
    // The IMU biases are the last six columns: accelerometer, then gyroscope.
    r.bias.acc = Vec3d(0.0166, -0.0237, 0.5);
    r.bias.gyro = Vec3d(1e-4, 0, -2.5e-3);
    const std::string with_bias = framesCsvLine(r, SE3d::Identity());
    const std::string header = framesCsvHeader();
    EXPECT_EQ(header.substr(header.size() - 47), "bias_ax,bias_ay,bias_az,bias_gx,bias_gy,bias_gz");
    EXPECT_EQ(with_bias.substr(with_bias.size() - 52),
              "0.01660,-0.02370,0.50000,0.000100,0.000000,-0.002500") << with_bias;
}
