// Association with a PriorMap (plane / line / point by the map's local shape) and the
// frames.csv writer's shape.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/localization/association.h>
#include <superloc/localization/localization_params.h>
#include <superloc/app/run_outputs.h>

#include <limits>
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

// A stair step inside one 0.5 m voxel smears its plane: the voxel association's plane there is
// tilted and thick, the nearest map point's neighbourhood is the tread itself.
// voxel_nearest_above hands such features (and those with no voxel) to the kd-tree.
TEST(Association, ThickVoxelsGoToTheNearestMapPoint) {
    PointCloud c;
    // Floor z = 0 for x < 0.25 m, a 0.17 m step up beyond (2 x 2 m, 2.5 cm grid), and the
    // step's riser. The step sits in the middle of the voxels [0, 0.5) along x.
    for (int i = 0; i < 80; ++i)
        for (int j = 0; j < 80; ++j) {
            const float x = -1.0f + 0.025f * i + 0.0125f, y = -1.0f + 0.025f * j + 0.0125f;
            c.points.emplace_back(x, y, x < 0.25f ? 0.1f : 0.27f);
        }
    for (int k = 0; k < 7; ++k)
        for (int j = 0; j < 80; ++j) c.points.emplace_back(0.25f, -1.0f + 0.025f * j + 0.0125f, 0.1f + 0.025f * k);
    map::MapParams mp;
    mp.voxel_size = 0;
    const map::PriorMap m(c, mp, Vec3f(0, 0, 2));
    // One feature on the lower tread inside the stepped voxel, one on the flat floor.
    const std::vector<Vec3d> pts = {Vec3d(0.15, 0.2, 0.1), Vec3d(-0.3, 0.2, 0.1)};
    AssociationParams ap;
    ap.voxel = true;
    ap.level = 0;
    std::vector<Correspondence> with_voxels, hybrid;
    AssociationStats st;
    associate(pts, SE3d::Identity(), m, ap, with_voxels, st);
    ASSERT_EQ(with_voxels.size(), 2u);
    // The stepped voxel's plane: its normal tilts toward x and the tread point is off it.
    EXPECT_GT(std::abs(with_voxels[0].n.x()), 0.1);
    EXPECT_GT(fusion::correspondenceError(with_voxels[0], SE3d::Identity()), 0.02);
    ap.nearest_above_thickness = 0.03;
    associate(pts, SE3d::Identity(), m, ap, hybrid, st);
    ASSERT_EQ(hybrid.size(), 2u);
    // Handed to the kd-tree: the tread's own plane, the point on it.
    EXPECT_NEAR(std::abs(hybrid[0].n.z()), 1.0, 1e-3);
    EXPECT_LT(fusion::correspondenceError(hybrid[0], SE3d::Identity()), 1e-3);
    EXPECT_NEAR(hybrid[0].q.z(), 0.1, 1e-6);  // a map point, not a voxel's centroid
    // The flat floor's voxel is thin: still the voxel's plane, through its centroid.
    EXPECT_NEAR(hybrid[1].q.x(), with_voxels[1].q.x(), 1e-9);
    EXPECT_NEAR(hybrid[1].n.dot(with_voxels[1].n), with_voxels[1].n.squaredNorm(), 1e-9);
}

TEST(Association, VoxelNearestAboveIsReadAndChecked) {
    mrpt::config::CConfigFileMemory ini;
    ini.write("localization", "association", "voxel");
    ini.write("localization", "voxel_nearest_above", 0.03);
    LocalizationParams p;
    p.loadFromConfigFile(ini, "localization");
    EXPECT_DOUBLE_EQ(p.voxel_nearest_above, 0.03);
    EXPECT_NO_THROW(p.validate());
    p.voxel_nearest_above = -0.01;
    EXPECT_THROW(p.validate(), ConfigError);
    p.voxel_nearest_above = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(p.validate(), ConfigError);
    EXPECT_DOUBLE_EQ(LocalizationParams{}.voxel_nearest_above, 0.0);  // off by default
}

// AssociationParams' defaults are the run's association (the default [localization] and
// [features]), so that a caller that builds one by hand associates as a run does.
TEST(Association, DefaultsAreTheRunsAssociation) {
    const AssociationParams d;
    const AssociationParams run = trackingAssociation(LocalizationParams{}, features::FeaturesParams{});
    EXPECT_EQ(d.voxel, run.voxel);
    EXPECT_EQ(d.level, run.level);
    EXPECT_EQ(d.nearest_above_thickness, run.nearest_above_thickness);
    EXPECT_EQ(d.max_dist, run.max_dist);
    EXPECT_EQ(d.plane_max_thickness, run.plane_max_thickness);
    EXPECT_EQ(d.line_min_linearity, run.line_min_linearity);
    EXPECT_EQ(d.max_fit_residual, run.max_fit_residual);
    EXPECT_EQ(d.point_weight, run.point_weight);
    EXPECT_EQ(d.line_knn, run.line_knn);
}

TEST(RunOutputs, CsvLineMatchesHeader) {
    FrameReport r;
    r.t = 12.5;
    r.degenerate_axes = "xyaw";
    r.diverged_reason = Divergence::Jump;
    const std::string line = framesCsvLine(r, makePoseRPY(1, 2, 3, 0, 0, 0.5));
    const auto count = [](const std::string& s) { return std::count(s.begin(), s.end(), ','); };
    EXPECT_EQ(count(line), count(framesCsvHeader()));
    EXPECT_EQ(line.rfind("12.500000000,1.000000,2.000000,3.000000,", 0), 0u) << line;
    EXPECT_NE(line.find(",xyaw,"), std::string::npos);
    // The IMU biases: accelerometer, then gyroscope; the estimate's std per axis (inf where
    // nothing holds it) after them.
    r.bias.acc = Vec3d(0.0166, -0.0237, 0.5);
    r.bias.gyro = Vec3d(1e-4, 0, -2.5e-3);
    r.est_sigma << 0.01, 0.002, 0.003, 1e-4, 2e-4, std::numeric_limits<double>::infinity();
    const auto split = [](const std::string& s) {
        std::vector<std::string> out(1);
        for (char c : s) {
            if (c == ',')
                out.emplace_back();
            else
                out.back().push_back(c);
        }
        return out;
    };
    const auto head = split(framesCsvHeader()), cells = split(framesCsvLine(r, SE3d::Identity()));
    ASSERT_EQ(head.size(), cells.size());
    const auto at = [&](const std::string& name) {
        const auto it = std::find(head.begin(), head.end(), name);
        return it == head.end() ? std::string("(no column ") + name + ")" : cells[size_t(it - head.begin())];
    };
    const char* bias[6] = {"bias_ax", "bias_ay", "bias_az", "bias_gx", "bias_gy", "bias_gz"};
    const char* want[6] = {"0.01660", "-0.02370", "0.50000", "0.000100", "0.000000", "-0.002500"};
    for (int k = 0; k < 6; ++k) EXPECT_EQ(at(bias[k]), want[k]) << bias[k];
    EXPECT_EQ(at("est_sigma_x"), "0.01");
    EXPECT_EQ(at("est_sigma_yaw"), "inf");
}
