// Association with a PriorMap (plane / line / point by the map's local shape) and the
// frames.csv writer's shape.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/localization/association.h>
#include <superloc/localization/localization_params.h>
#include <superloc/app/run_outputs.h>

#include "box_room.h"

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

namespace {
// Floor z = 0.1 for x < 0.25 m, a 0.17 m step up beyond (2 x 2 m, 2.5 cm grid), and the step's
// riser at x = 0.25: the voxels [0, 0.5) along x hold a riser and two treads.
PointCloud floorWithStep() {
    PointCloud c;
    for (int i = 0; i < 80; ++i)
        for (int j = 0; j < 80; ++j) {
            const float x = -1.0f + 0.025f * i + 0.0125f, y = -1.0f + 0.025f * j + 0.0125f;
            c.points.emplace_back(x, y, x < 0.25f ? 0.1f : 0.27f);
        }
    for (int k = 0; k < 7; ++k)
        for (int j = 0; j < 80; ++j) c.points.emplace_back(0.25f, -1.0f + 0.025f * j + 0.0125f, 0.1f + 0.025f * k);
    return c;
}
}  // namespace

// A stair step inside one 0.5 m voxel smears its plane: the voxel association's plane there is
// tilted and thick, the nearest map point's neighbourhood is the tread itself.
// voxel_nearest_above hands such features (and those with no voxel) to the kd-tree.
TEST(Association, ThickVoxelsGoToTheNearestMapPoint) {
    map::MapParams mp;
    mp.voxel_size = 0;
    const map::PriorMap m(floorWithStep(), mp, Vec3f(0, 0, 2));
    // One feature on the lower tread inside the stepped voxel, one on the flat floor.
    const std::vector<Vec3d> pts = {Vec3d(0.15, 0.2, 0.1), Vec3d(-0.3, 0.2, 0.1)};
    AssociationParams ap;
    ap.kind = AssociationKind::Voxel;
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

TEST(Association, SectionIsReadAndChecked) {
    mrpt::config::CConfigFileMemory ini;
    ini.write("association", "kind", "voxel");
    ini.write("association", "voxel_nearest_above", 0.03);
    ini.write("association", "plane_thickness", 0.02);
    const AssociationConfig p = loadParams<AssociationConfig>(ini, "association", "test.ini");
    EXPECT_EQ(p.kind, AssociationKind::Voxel);
    EXPECT_DOUBLE_EQ(p.voxel_nearest_above, 0.03);
    EXPECT_DOUBLE_EQ(p.plane.thickness, 0.02);
    AssociationConfig bad = p;
    bad.voxel_nearest_above = -0.01;
    EXPECT_THROW(bad.validate(), ConfigError);
    bad = p;
    bad.voxel_nearest_above = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(bad.validate(), ConfigError);
    bad = p;
    bad.plane.thickness = 0;
    EXPECT_THROW(bad.validate(), ConfigError);
    EXPECT_DOUBLE_EQ(AssociationConfig{}.voxel_nearest_above, 0.0);  // off by default
    EXPECT_EQ(AssociationConfig{}.kind, AssociationKind::Planes);    // the default
    // A bad kind is one line naming the section and the key.
    mrpt::config::CConfigFileMemory wrong;
    wrong.write("association", "kind", "kdtree");
    try {
        loadParams<AssociationConfig>(wrong, "association", "test.ini");
        ADD_FAILURE() << "no error";
    } catch (const ConfigError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("[association] kind"), std::string::npos) << m;
        EXPECT_NE(m.find("kdtree"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    // The old [localization] key is gone: an unknown key there.
    mrpt::config::CConfigFileMemory old;
    old.write("localization", "association", "voxel");
    EXPECT_THROW(loadParams<LocalizationParams>(old, "localization", "old.ini"), ConfigError);
}

// AssociationParams' defaults are the run's association (the default [association],
// [localization] and [features]), so that a caller that builds one by hand associates as a run does.
TEST(Association, DefaultsAreTheRunsAssociation) {
    const AssociationParams d;
    const AssociationParams run =
        trackingAssociation(AssociationConfig{}, LocalizationParams{}, features::FeaturesParams{});
    EXPECT_EQ(d.kind, run.kind);
    EXPECT_EQ(d.kind, AssociationKind::Planes);
    EXPECT_EQ(d.plane.min_points, run.plane.min_points);
    EXPECT_EQ(d.plane.thickness, run.plane.thickness);
    EXPECT_EQ(d.plane.min_spread, run.plane.min_spread);
    EXPECT_EQ(d.plane.footprint, run.plane.footprint);
    EXPECT_EQ(d.plane.gate, run.plane.gate);
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

// ---- planes: validated voxel planes, else the nearest map point within the grid's cell --------

TEST(PlanesAssociation, FlatVoxelGivesItsPlaneSteppedVoxelFallsBackToTheTread) {
    map::MapParams mp;
    mp.voxel_size = 0;
    const map::PriorMap m(floorWithStep(), mp, Vec3f(0, 0, 2));
    // On the flat floor (voxel [-0.5, 0)), on the lower tread inside the stepped voxel, and 1.15 m
    // above the floor (beyond max_dist, 1 m: none, from the grid's 125 cells as from the kd-tree).
    const std::vector<Vec3d> pts = {Vec3d(-0.3, 0.2, 0.12), Vec3d(0.15, 0.2, 0.11), Vec3d(-0.3, 0.2, 1.25)};
    AssociationParams ap;  // the default: planes
    ASSERT_EQ(ap.kind, AssociationKind::Planes);
    std::vector<Correspondence> corr;
    std::vector<uint32_t> feature_of;
    AssociationStats st;
    associate(pts, SE3d::Identity(), m, ap, corr, st, &feature_of);
    ASSERT_EQ(corr.size(), 2u);
    EXPECT_EQ(st.voxel_planes, 1u);
    EXPECT_EQ(st.plane, 2u);
    EXPECT_EQ(st.too_far, 1u);
    ASSERT_EQ(feature_of, (std::vector<uint32_t>{0, 1}));
    // The flat floor: its voxel's plane through the voxel's centroid (not a map point).
    const map::VoxelStats* v = m.voxels().find(0, Vec3f(-0.3f, 0.2f, 0.12f));
    ASSERT_NE(v, nullptr);
    EXPECT_NEAR((corr[0].q - v->mean.cast<double>()).norm(), 0.0, 1e-6);
    EXPECT_NEAR(std::abs(corr[0].n.z()), 1.0, 1e-4);
    EXPECT_NEAR(fusion::correspondenceError(corr[0], SE3d::Identity()), 0.02, 1e-4);
    // The stepped voxel is thick (its plane is the diagonal through the steps): the tread's own
    // plane at its nearest map point instead, as `nearest` gives it.
    const map::VoxelStats* stepped = m.voxels().find(0, Vec3f(0.15f, 0.2f, 0.11f));
    ASSERT_NE(stepped, nullptr);
    EXPECT_GT(stepped->thickness, ap.plane.thickness);
    EXPECT_NEAR(std::abs(corr[1].n.z()), 1.0, 1e-3);
    EXPECT_NEAR(corr[1].q.z(), 0.1, 1e-6);
    EXPECT_NEAR(fusion::correspondenceError(corr[1], SE3d::Identity()), 0.01, 1e-3);
    // 0.7 m above the floor: within max_dist, found in the grid's second ring of cells.
    std::vector<Correspondence> up;
    associate({Vec3d(-0.3, 0.2, 0.8)}, SE3d::Identity(), m, ap, up, st);
    ASSERT_EQ(up.size(), 1u);
    EXPECT_NEAR(fusion::correspondenceError(up[0], SE3d::Identity()), 0.7, 1e-3);
    ap.max_dist = 0.5;  // the bound: nothing within it, none
    associate({Vec3d(-0.3, 0.2, 0.8)}, SE3d::Identity(), m, ap, up, st);
    EXPECT_TRUE(up.empty());
    EXPECT_EQ(st.too_far, 1u);
    ap.max_dist = 1.0;
    std::vector<Correspondence> nn;
    ap.kind = AssociationKind::Nearest;
    associate(pts, SE3d::Identity(), m, ap, nn, st);
    ASSERT_EQ(nn.size(), 2u);
    EXPECT_EQ(st.too_far, 1u);
    EXPECT_NEAR((nn[1].q - corr[1].q).norm(), 0.0, 1e-9);
    EXPECT_NEAR(nn[1].n.dot(corr[1].n), 1.0, 1e-9);
}

TEST(PlanesAssociation, OutsideThePlanesFootprintFallsBack) {
    // A wall (x = 0) covering only z in [0, 0.2) of the voxels [0, 0.5) in z: a feature in the
    // same voxel at z = 0.45 projects beyond the wall's top edge; its voxel's plane is not used.
    PointCloud c;
    for (int j = 0; j < 80; ++j)
        for (int k = 0; k < 8; ++k) c.points.emplace_back(0.1f, -1.0f + 0.025f * j + 0.0125f, 0.0125f + 0.025f * k);
    map::MapParams mp;
    mp.voxel_size = 0;
    const map::PriorMap m(c, mp, Vec3f(2, 0, 1));
    AssociationParams ap;
    std::vector<Correspondence> corr;
    AssociationStats st;
    associate({Vec3d(0.12, 0.2, 0.1), Vec3d(0.12, 0.2, 0.45)}, SE3d::Identity(), m, ap, corr, st);
    EXPECT_EQ(st.voxel_planes, 1u);  // the first, on the wall
    EXPECT_EQ(st.plane + st.line + st.point + st.too_far, 2u);
}

TEST(PlanesAssociation, AnswersLikeNearestInABoxRoom) {
    // The box room's surfaces (5 cm grid) and features 1-3 cm off them, seen from inside: the
    // same correspondences as the kd-tree's (same planes, residuals within a millimetre), most
    // of them from the voxel planes. The room is shifted off the voxel grid's faces (a wall on a
    // face leaves the voxels on its inner side empty: those features would all fall back).
    const Vec3f shift(0.23f, 0.17f, 0.11f);
    PointCloud room = superloc::testing::boxSurface(0.05);
    for (auto& q : room.points) q += shift;
    map::MapParams mp;
    const map::PriorMap m(room, mp, Vec3f(0, 0, 1.5f));
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(0, 1);
    std::vector<Vec3d> pts;
    const Vec3d lo = superloc::testing::kRoomMin, hi = superloc::testing::kRoomMax;
    for (int i = 0; i < 1500; ++i) {
        Vec3d x(lo.x() + 0.3 + (hi.x() - lo.x() - 0.6) * U(rng), lo.y() + 0.3 + (hi.y() - lo.y() - 0.6) * U(rng),
                lo.z() + 0.3 + (hi.z() - lo.z() - 0.6) * U(rng));
        const int axis = i % 3;
        x[axis] = (i / 3) % 2 ? hi[axis] - (0.01 + 0.02 * U(rng)) : lo[axis] + 0.01 + 0.02 * U(rng);
        pts.push_back(x + shift.cast<double>());
    }
    const SE3d T = makePoseRPY(0.3, -0.2, 1.2, 0.02, -0.01, 0.4);
    std::vector<Vec3d> body;
    for (const auto& x : pts) body.push_back(T.inverse() * x);
    AssociationParams ap;
    std::vector<Correspondence> planes, nearest;
    std::vector<uint32_t> of_planes, of_nearest;
    AssociationStats sp, sn;
    associate(body, T, m, ap, planes, sp, &of_planes);
    ap.kind = AssociationKind::Nearest;
    associate(body, T, m, ap, nearest, sn, &of_nearest);
    EXPECT_GT(sp.voxel_planes, pts.size() * 8 / 10);
    EXPECT_EQ(sp.too_far, 0u);
    // Every feature the kd-tree associates as a plane, planes associates too, with the same
    // normal and residual.
    std::vector<int> at(pts.size(), -1);
    for (size_t k = 0; k < planes.size(); ++k) at[of_planes[k]] = static_cast<int>(k);
    size_t compared = 0;
    for (size_t k = 0; k < nearest.size(); ++k) {
        if (nearest[k].type != FeatureType::Plane) continue;
        const int j = at[of_nearest[k]];
        ASSERT_GE(j, 0) << "feature " << of_nearest[k];
        const Correspondence& a = planes[static_cast<size_t>(j)];
        EXPECT_EQ(a.type, FeatureType::Plane);
        EXPECT_GT(std::abs(a.n.dot(nearest[k].n)), std::cos(2.0 * M_PI / 180));
        EXPECT_NEAR(fusion::correspondenceError(a, T), fusion::correspondenceError(nearest[k], T), 1e-3);
        ++compared;
    }
    EXPECT_GT(compared, pts.size() * 9 / 10);
    // Without voxel planes (a frame weak in translation, IcpRegistration) every feature takes the
    // bounded fallback: the kd-tree's answer exactly, its map point and that point's geometry.
    ap.kind = AssociationKind::Planes;
    ap.voxel_planes = false;
    std::vector<Correspondence> points;
    std::vector<uint32_t> of_points;
    AssociationStats sq;
    associate(body, T, m, ap, points, sq, &of_points);
    EXPECT_EQ(sq.voxel_planes, 0u);
    ASSERT_EQ(points.size(), nearest.size());
    EXPECT_EQ(of_points, of_nearest);
    for (size_t k = 0; k < points.size(); ++k) {
        EXPECT_EQ(points[k].type, nearest[k].type);
        EXPECT_LT((points[k].q - nearest[k].q).norm(), 1e-9);
        EXPECT_LT((points[k].n - nearest[k].n).norm(), 1e-9);
        EXPECT_DOUBLE_EQ(points[k].weight, nearest[k].weight);
    }
}

TEST(PlanesAssociation, TheMemoAnswersExactlyAsTheSearch) {
    // A solve's rounds: the same features associated at poses a few millimetres to centimetres
    // apart, with and without the memo (and the hint, as IcpRegistration uses both). Every
    // round's correspondences are the same, bit for bit; from the second round on, most
    // fallback features are answered from the memo.
    const Vec3f shift(0.23f, 0.17f, 0.11f);
    PointCloud room = superloc::testing::boxSurface(0.05);
    for (auto& q : room.points) q += shift;
    // Poles inside the room: line correspondences as well as planes.
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> U(0, 1);
    const Vec3d lo = superloc::testing::kRoomMin, hi = superloc::testing::kRoomMax;
    std::vector<Vec3d> poles;
    for (const double fx : {0.3, 0.7})
        for (const double fy : {0.35, 0.65}) poles.push_back(Vec3d(lo.x() + fx * (hi.x() - lo.x()), lo.y() + fy * (hi.y() - lo.y()), 0));
    for (const Vec3d& pole : poles)
        for (double z = lo.z(); z < hi.z(); z += 0.01) room.points.push_back(Vec3f(pole.x(), pole.y(), z) + shift);
    map::MapParams mp;
    const map::PriorMap m(room, mp, Vec3f(0, 0, 1.5f));
    std::vector<Vec3d> body;
    const SE3d T0 = makePoseRPY(0.3, -0.2, 1.2, 0.02, -0.01, 0.4);
    for (int i = 0; i < 1500; ++i) {
        Vec3d x(lo.x() + (hi.x() - lo.x()) * U(rng), lo.y() + (hi.y() - lo.y()) * U(rng), lo.z() + (hi.z() - lo.z()) * U(rng));
        if (i % 4) {  // most on a surface, 0-3 cm off it; the rest 0-5 cm off a pole
            const int axis = i % 3;
            x[axis] = (i / 3) % 2 ? hi[axis] - 0.03 * U(rng) : lo[axis] + 0.03 * U(rng);
        } else {
            const Vec3d& pole = poles[static_cast<size_t>(i / 4) % poles.size()];
            x.x() = pole.x() + 0.1 * (U(rng) - 0.5), x.y() = pole.y() + 0.1 * (U(rng) - 0.5);
        }
        body.push_back(T0.inverse() * (x + shift.cast<double>()));
    }
    for (const bool voxel_planes : {false, true}) {
        AssociationParams ap;
        ap.voxel_planes = voxel_planes;
        std::vector<uint32_t> hint_a, hint_b;
        AssociationMemo memo;
        SE3d T = T0;
        size_t reused = 0;
        for (int round = 0; round < 6; ++round) {
            std::vector<Correspondence> a, b;
            std::vector<uint32_t> of_a, of_b;
            AssociationStats sa, sb;
            associate(body, T, m, ap, a, sa, &of_a, &hint_a);
            associate(body, T, m, ap, b, sb, &of_b, &hint_b, &memo);
            ASSERT_EQ(a.size(), b.size()) << "round " << round;
            EXPECT_EQ(of_a, of_b);
            EXPECT_EQ(hint_a, hint_b);
            EXPECT_EQ(sa.plane, sb.plane);
            EXPECT_EQ(sa.line, sb.line);
            EXPECT_EQ(sa.point, sb.point);
            EXPECT_EQ(sa.too_far, sb.too_far);
            EXPECT_EQ(sa.voxel_planes, sb.voxel_planes);
            for (size_t k = 0; k < a.size(); ++k) {
                ASSERT_EQ(a[k].type, b[k].type);
                ASSERT_EQ(a[k].q, b[k].q);
                ASSERT_EQ(a[k].n, b[k].n);
                ASSERT_EQ(a[k].p, b[k].p);
                ASSERT_EQ(a[k].weight, b[k].weight);
            }
            if (round == 0) {
                EXPECT_EQ(memo.reused, 0u);
                EXPECT_GT(sa.line, 100u) << "the poles give lines";
            }
            reused += memo.reused;
            // The next round's pose: steps shrinking from 2 cm / 0.5 deg, as a solve's do.
            const double s = 0.02 * std::pow(0.4, round);
            T = T * makePoseRPY(s * (U(rng) - 0.5), s * (U(rng) - 0.5), s * (U(rng) - 0.5), 25 * s * (U(rng) - 0.5) * M_PI / 180,
                                25 * s * (U(rng) - 0.5) * M_PI / 180, 25 * s * (U(rng) - 0.5) * M_PI / 180);
        }
        EXPECT_GT(reused, voxel_planes ? 300u : 3000u) << "voxel planes " << voxel_planes;
    }
    // A memo of another feature set (or max_dist) is not used: the first round searches all.
    AssociationParams ap;
    ap.voxel_planes = false;
    AssociationMemo memo;
    std::vector<Correspondence> c;
    AssociationStats st;
    associate(body, T0, m, ap, c, st, nullptr, nullptr, &memo);
    std::vector<Vec3d> fewer(body.begin(), body.begin() + 1000);
    associate(fewer, T0, m, ap, c, st, nullptr, nullptr, &memo);
    EXPECT_EQ(memo.reused, 0u);
    ap.max_dist = 0.5;
    associate(fewer, T0, m, ap, c, st, nullptr, nullptr, &memo);
    EXPECT_EQ(memo.reused, 0u);
    associate(fewer, T0, m, ap, c, st, nullptr, nullptr, &memo);
    EXPECT_GT(memo.reused, 500u);
    // Another feature vector of the same size (another solve's), or another map: afresh.
    const std::vector<Vec3d> other(fewer.rbegin(), fewer.rend());
    associate(other, T0, m, ap, c, st, nullptr, nullptr, &memo);
    EXPECT_EQ(memo.reused, 0u);
    const map::PriorMap m2(room, mp, Vec3f(0, 0, 1.5f));
    associate(other, T0, m2, ap, c, st, nullptr, nullptr, &memo);
    EXPECT_EQ(memo.reused, 0u);
    associate(other, T0, m2, ap, c, st, nullptr, nullptr, &memo);
    EXPECT_GT(memo.reused, 500u);
}

TEST(PlanesAssociation, ASurfaceBeyondTheVoxelsFaceIsNotHiddenByItsPlane) {
    // A floor (z = 0.1) and a wall standing exactly on a voxel face (x = 0.5): the voxel
    // [0, 0.5)^3 holds the floor alone, thin and valid. A feature 2 cm off the wall, 20 cm above
    // the floor, sits in that voxel: its surface is the wall beyond the face (2 cm), not the
    // floor's plane (20 cm), as the kd-tree says.
    PointCloud c;
    for (int i = 0; i < 80; ++i)
        for (int j = 0; j < 80; ++j) {
            const float x = -1.0f + 0.025f * i + 0.0125f, y = -1.0f + 0.025f * j + 0.0125f;
            if (x < 0.5f) c.points.emplace_back(x, y, 0.1f);
        }
    for (int k = 0; k < 40; ++k)
        for (int j = 0; j < 80; ++j) c.points.emplace_back(0.5f, -1.0f + 0.025f * j + 0.0125f, 0.1125f + 0.025f * k);
    map::MapParams mp;
    mp.voxel_size = 0;
    const map::PriorMap m(c, mp, Vec3f(0, 0, 1));
    const std::vector<Vec3d> pts = {Vec3d(0.48, 0.2, 0.3), Vec3d(0.2, 0.2, 0.12)};
    AssociationParams ap;
    std::vector<Correspondence> planes, nearest;
    AssociationStats st;
    associate(pts, SE3d::Identity(), m, ap, planes, st);
    ASSERT_EQ(planes.size(), 2u);
    EXPECT_EQ(st.voxel_planes, 1u);  // the floor feature only
    EXPECT_NEAR(std::abs(planes[0].n.x()), 1.0, 1e-3);
    EXPECT_NEAR(fusion::correspondenceError(planes[0], SE3d::Identity()), 0.02, 1e-3);
    ap.kind = AssociationKind::Nearest;
    associate(pts, SE3d::Identity(), m, ap, nearest, st);
    ASSERT_EQ(nearest.size(), 2u);
    EXPECT_NEAR(nearest[0].n.dot(planes[0].n), 1.0, 1e-9);
}
