#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/risk/alignment_risk.h>

#include <cmath>
#include <limits>

#include "scenes.h"

using namespace superloc;
using namespace superloc::risk;
using superloc::risk::testing::AxisPlane;
using superloc::risk::testing::castScene;

namespace {
Correspondence corr(Vec3d p, Vec3d n, double w = 1.0) {
    Correspondence c;
    c.p = p;
    c.n = n;
    c.weight = w;
    return c;
}
std::string flags(const std::vector<Correspondence>& cs) {
    return degenerateAxes(computeAlignmentRisk(cs, RiskParams{}));
}
}  // namespace

// Hand-computed: three correspondences.
//  a: p=(2,0,0)  n=(0,0,1)  -> t label z; p x n = (0*1-0*0, 0*0-2*1, 0) = (0,-2,0) -> pitch
//  b: p=(0,3,0)  n=(0,0,1)  -> z;         p x n = (3,0,0)                        -> roll
//  c: p=(0,3,0)  n=(1,0,0)  -> x;         p x n = (3*0-0*0, 0*1-0*0, 0*0-3*1) = (0,0,-3) -> yaw
// Translation: N=(1,0,2) -> gamma = (3*1/3, 0, min(1, 3*2/3)) = (1, 0, 1).
// Rotation: N=(1,1,1) -> gamma = (1,1,1). Only y is degenerate.
TEST(AlignmentRisk, HandComputedLabelsAndGamma) {
    RiskParams prm;
    prm.keep_jacobians = true;
    const auto r = computeAlignmentRisk(
        {corr({2, 0, 0}, {0, 0, 1}), corr({0, 3, 0}, {0, 0, 1}), corr({0, 3, 0}, {1, 0, 0})}, prm);
    EXPECT_EQ(r.translation_label, (std::vector<int8_t>{2, 2, 0}));
    EXPECT_EQ(r.rotation_label, (std::vector<int8_t>{4, 3, 5}));
    Vec6d counts;
    counts << 1, 0, 2, 1, 1, 1;
    EXPECT_TRUE(r.counts.isApprox(counts));
    Vec6d gamma;
    gamma << 1, 0, 1, 1, 1, 1;
    EXPECT_TRUE(r.gamma.isApprox(gamma)) << r.gamma.transpose();
    EXPECT_EQ(degenerateAxes(r), "y");
    ASSERT_EQ(r.jacobians.size(), 3u);
    Vec6d j2;
    j2 << 1, 0, 0, 0, 0, -3;
    EXPECT_TRUE(r.jacobians[2].isApprox(j2));
    // H = sum J J^T: H(y,y) = 0 (no normal has a y part), H(yaw,yaw) = 9, H(pitch,pitch) = 4.
    EXPECT_DOUBLE_EQ(r.hessian(1, 1), 0.0);
    EXPECT_DOUBLE_EQ(r.hessian(5, 5), 9.0);
    EXPECT_DOUBLE_EQ(r.hessian(4, 4), 4.0);
    EXPECT_NEAR(r.eigenvalues[0], 0.0, 1e-9);
    EXPECT_TRUE(std::isinf(r.condition_number));
}

// Weighted counts: two z-labels of weight 0.5 and 0.1 and one x-label of weight 1:
// N = (1, 0, 0.6); gamma_x = min(1, 3/1.6) = 1, gamma_z = 3*0.6/1.6 = 1.125 -> 1, gamma_y = 0.
// Unweighted, the same set gives N = (1, 0, 2).
// Two rotation labels (default): p = (1,0,2), n = (0,1,0): p x n = (0*0-2*1, 2*0-1*0, 1*1-0*0)
// = (-2, 0, 1) -> first label roll, second yaw (pitch component 0: no label).
// N_rot = (1, 0, 1) -> gamma_rot = (min(1, 3/2), 0, min(1, 3/2)) = (1, 0, 1).
// With one label only roll counts: gamma_rot = (1, 0, 0).
TEST(AlignmentRisk, TwoRotationLabelsHandComputed) {
    const std::vector<Correspondence> cs = {corr({1, 0, 2}, {0, 1, 0})};
    const auto r2 = computeAlignmentRisk(cs, RiskParams{});
    EXPECT_EQ(r2.rotation_label[0], 3);
    EXPECT_EQ(r2.rotation_label2[0], 5);
    EXPECT_TRUE(r2.gamma.tail<3>().isApprox(Eigen::Vector3d(1, 0, 1))) << r2.gamma.transpose();
    RiskParams one;
    one.rotation_labels = 1;
    const auto r1 = computeAlignmentRisk(cs, one);
    EXPECT_EQ(r1.rotation_label2[0], kNoLabel);
    EXPECT_TRUE(r1.gamma.tail<3>().isApprox(Eigen::Vector3d(1, 0, 0))) << r1.gamma.transpose();
}

TEST(AlignmentRisk, WeightsCountFractionally) {
    const std::vector<Correspondence> cs = {corr({1, 1, 0}, {0, 0, 1}, 0.5),
                                            corr({1, 2, 0}, {0, 0, 1}, 0.1),
                                            corr({0, 1, 1}, {1, 0, 0}, 1.0)};
    const auto r = computeAlignmentRisk(cs, RiskParams{});
    EXPECT_NEAR(r.counts[0], 1.0, 1e-12);
    EXPECT_NEAR(r.counts[2], 0.6, 1e-12);
    EXPECT_NEAR(r.gamma[2], 1.0, 1e-12);
    // Four x labels of weight 1 and one z of weight 0.1: gamma_z = 3*0.1/4.1 = 0.0732 < 0.2.
    std::vector<Correspondence> cs2(4, corr({0, 1, 1}, {1, 0, 0}, 1.0));
    cs2.push_back(corr({1, 1, 0}, {0, 0, 1}, 0.1));
    EXPECT_NEAR(computeAlignmentRisk(cs2, RiskParams{}).gamma[2], 0.3 / 4.1, 1e-12);
    RiskParams unweighted;
    unweighted.weighted_labels = false;
    EXPECT_NEAR(computeAlignmentRisk(cs2, unweighted).gamma[2], 3.0 / 5.0, 1e-12);
}

TEST(AlignmentRisk, EmptyAndInvalidInputAreAllDegenerate) {
    const auto empty = computeAlignmentRisk({}, RiskParams{});
    EXPECT_TRUE(empty.gamma.isZero());
    EXPECT_EQ(degenerateAxes(empty), "xyzrollpitchyaw");
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const auto bad = computeAlignmentRisk(
        {corr({nan, 0, 0}, {0, 0, 1}), corr({1, 0, 0}, {0, 0, 0}), corr({1, 0, 0}, {0, 0, 1}, 0)},
        RiskParams{});
    EXPECT_EQ(bad.skipped, 3u);
    EXPECT_EQ(bad.translation_label, (std::vector<int8_t>(3, kNoLabel)));
    EXPECT_TRUE(bad.counts.isZero());
}

// A point straight below the sensor on the floor has p parallel to n: no lever arm, no
// rotation label; its translation label still counts.
TEST(AlignmentRisk, ZeroLeverArmHasNoRotationLabel) {
    const auto r = computeAlignmentRisk({corr({0, 0, -2}, {0, 0, 1})}, RiskParams{});
    EXPECT_EQ(r.translation_label[0], 2);
    EXPECT_EQ(r.rotation_label[0], kNoLabel);
    EXPECT_EQ(r.gamma[2], 1.0);
    EXPECT_EQ(r.gamma.tail<3>().sum(), 0.0);
}

// The three failure-prediction rules come from the same correspondences whatever
// rotation_labels selects: the single correspondence above has one rotation label (roll) and a
// second (yaw), so labels1 flags pitch and yaw, labels2 pitch only; its translation block is
// n n^T with n = y (x, z flagged by both labels and eigenvalues). Its rotation block is the one
// torque direction (-2, 0, 1)/sqrt5: the degenerate subspace is the plane orthogonal to it,
// projector diagonal 1 - (4/5, 0, 1/5) = (0.2, 1, 0.8): pitch and yaw flagged, roll not.
TEST(AlignmentRisk, RuleFlagsFromTheSameCorrespondences) {
    const std::vector<Correspondence> cs = {corr({1, 0, 2}, {0, 1, 0})};
    for (int labels : {1, 2}) {
        RiskParams p;
        p.rotation_labels = labels;
        const auto r = computeAlignmentRisk(cs, p);
        EXPECT_EQ(axisLetters(r.rules.labels1), "xzpitchyaw");
        EXPECT_EQ(axisLetters(r.rules.labels2), "xzpitch");
        EXPECT_EQ(axisLetters(r.rules.eigen), "xzpitchyaw");
        EXPECT_EQ(r.degenerate, labels == 1 ? r.rules.labels1 : r.rules.labels2);
    }
}

// Corridor: every rule flags x and only x; a box room: no rule flags anything; no
// correspondence: every rule flags every axis.
TEST(AlignmentRisk, RulesAgreeOnCorridorRoomAndNothing) {
    const auto corridor = computeAlignmentRisk(castScene({{1, -1.5}, {1, 1.6}, {2, -1.2}, {2, 1.4}}), RiskParams{});
    EXPECT_EQ(axisLetters(corridor.rules.labels1), "x");
    EXPECT_EQ(axisLetters(corridor.rules.labels2), "x");
    EXPECT_EQ(axisLetters(corridor.rules.eigen), "x");
    const auto room = computeAlignmentRisk(
        castScene({{0, -4}, {0, 8}, {1, -3.5}, {1, 5.5}, {2, -1.2}, {2, 1.8}}), RiskParams{});
    for (const auto& f : {room.rules.labels1, room.rules.labels2, room.rules.eigen}) EXPECT_EQ(axisLetters(f), "");
    const auto none = computeAlignmentRisk({}, RiskParams{});
    for (const auto& f : {none.rules.labels1, none.rules.labels2, none.rules.eigen})
        EXPECT_EQ(axisLetters(f), "xyzrollpitchyaw");
}

// An infinite floor 1.8 m below the sensor: every normal is z; p x n = (y, -x, 0) never has a
// yaw part. Degenerate: x, y, yaw. Healthy: z, roll, pitch.
class SceneTest : public ::testing::TestWithParam<int> {
 protected:
    RiskParams params() const {
        RiskParams p;
        p.rotation_labels = GetParam();
        return p;
    }
};
INSTANTIATE_TEST_SUITE_P(RotationLabels, SceneTest, ::testing::Values(1, 2));

TEST_P(SceneTest, InfinitePlaneIsDegenerateInXYYaw) {
    const auto cs = castScene({{2, -1.8}}, 360, 32, -45, -5, 1e6);
    ASSERT_GT(cs.size(), 1000u);
    const auto r = computeAlignmentRisk(cs, params());
    EXPECT_EQ(degenerateAxes(r), "xyyaw");
    EXPECT_EQ(r.gamma[2], 1.0);
    EXPECT_GT(r.gamma[3], 0.9);
    EXPECT_GT(r.gamma[4], 0.9);
    EXPECT_EQ(r.counts[5], 0.0);
    // The classic analysis agrees: three zero eigenvalues (x, y, yaw).
    EXPECT_NEAR(r.eigenvalues[2] / r.eigenvalues[5], 0.0, 1e-9);
    EXPECT_GT(r.eigenvalues[3], 1.0);
}

// A corridor along x: walls at y = -1.5, +1.6, floor at z = -1.2, ceiling at z = +1.4, open ends
// (returns up to 30 m). Only x is degenerate.
TEST_P(SceneTest, CorridorIsDegenerateInXOnly) {
    const auto cs = castScene({{1, -1.5}, {1, 1.6}, {2, -1.2}, {2, 1.4}});
    const auto r = computeAlignmentRisk(cs, params());
    EXPECT_EQ(degenerateAxes(r), "x") << r.gamma.transpose();
    EXPECT_EQ(r.counts[0], 0.0);
    EXPECT_GT(r.gamma.tail<5>().minCoeff(), 0.2);
}

// The translational information T = sum w n n^T / sum w (rotation-invariant, trace 1) agrees
// with the labels on axis-aligned scenes and finds the weak direction of a tilted one, where
// the axis-aligned labels split it.
TEST(AlignmentRisk, TranslationEigenDiagnostics) {
    const auto corridor = computeAlignmentRisk(castScene({{1, -1.5}, {1, 1.6}, {2, -1.2}, {2, 1.4}}),
                                               RiskParams{});
    EXPECT_NEAR(corridor.translation_eigenvalues.sum(), 1.0, 1e-9);
    EXPECT_LT(corridor.translation_eigenvalues[0], 1e-9);
    EXPECT_GT(corridor.translation_eigenvalues[1], 0.25);
    EXPECT_NEAR(corridor.weakest_translation.x(), 1.0, 1e-9);
    EXPECT_GT(corridor.weight_sum, 1000);

    const auto room = computeAlignmentRisk(
        castScene({{0, -4}, {0, 8}, {1, -3.5}, {1, 5.5}, {2, -1.2}, {2, 1.8}}), RiskParams{});
    EXPECT_GT(room.translation_eigenvalues[0], 0.1);

    // The same corridor pitched by 30 deg about y (points and normals rotated): the weakest
    // direction is the rotated x axis (cos 30, 0, -sin 30) up to sign, still an exact zero.
    auto tilted = castScene({{1, -1.5}, {1, 1.6}, {2, -1.2}, {2, 1.4}});
    const Mat3d R = Eigen::AngleAxisd(30.0 * M_PI / 180.0, Vec3d::UnitY()).toRotationMatrix();
    for (auto& c : tilted) {
        c.p = R * c.p;
        c.n = R * c.n;
    }
    const auto rt = computeAlignmentRisk(tilted, RiskParams{});
    EXPECT_LT(rt.translation_eigenvalues[0], 1e-9);
    EXPECT_NEAR(std::abs(rt.weakest_translation.dot(R * Vec3d::UnitX())), 1.0, 1e-9);
    EXPECT_GT(rt.weakest_translation.x(), 0.0);  // sign convention: largest component positive
}

// The information C = sum w J J^T is the sum Eigen's rank-one update makes, bit for bit (the
// risk writes the 6 x 6 update out for speed; the solve's weighting reads the same H, so any
// change of its arithmetic would move every trajectory: doc/results.md "Cost of the risk").
TEST(AlignmentRisk, HessianIsEigensRankUpdateBitForBit) {
    auto cs = castScene({{0, -4}, {0, 8}, {1, -3.5}, {1, 5.5}, {2, -1.2}, {2, 1.8}}, 90, 16);
    for (size_t i = 0; i < cs.size(); ++i) cs[i].weight = 0.3 + 0.7 * std::sin(0.37 * static_cast<double>(i)) * std::sin(0.37 * static_cast<double>(i));
    RiskParams prm;
    prm.keep_jacobians = true;
    const auto r = computeAlignmentRisk(cs, SE3d::Identity(), Vec3d(0.1, -0.2, 0.05), prm);
    ASSERT_EQ(r.jacobians.size(), cs.size());
    Mat6d H = Mat6d::Zero();
    for (size_t i = 0; i < cs.size(); ++i)
        if (r.translation_label[i] != kNoLabel) H.selfadjointView<Eigen::Lower>().rankUpdate(r.jacobians[i], cs[i].weight);
    H = H.selfadjointView<Eigen::Lower>();
    for (int i = 0; i < 6; ++i)
        for (int k = 0; k < 6; ++k) EXPECT_EQ(r.hessian(i, k), H(i, k)) << i << "," << k;
    EXPECT_GT(H.trace(), 100.0);
}

// The risk works on blocks of 64 correspondences: a correspondence's labels and Jacobian are
// those it gets alone, wherever it falls in a block (sizes across block boundaries, planes,
// lines and points in a turned frame, skipped ones among them), and the counts add up.
TEST(AlignmentRisk, BlocksGiveEachCorrespondenceItsOwnResult) {
    auto base = castScene({{0, -4}, {0, 8}, {1, -3.5}, {1, 5.5}, {2, -1.2}, {2, 1.8}}, 90, 16);
    ASSERT_GT(base.size(), 200u);
    const SE3d T = makePoseRPY(1.0, -2.0, 0.3, 0.05, -0.02, 0.7);
    for (size_t i = 0; i < base.size(); ++i) {
        Correspondence& c = base[i];
        c.q = T * c.p + Vec3d(0.01, -0.02, 0.015);
        if (i % 7 == 3) c.type = FeatureType::Line, c.n = Vec3d(1, 2, 0.5).normalized();
        if (i % 11 == 5) c.type = FeatureType::Point;
        if (i % 13 == 6) c.weight = 0;  // skipped
        if (i % 17 == 8) c.p = Vec3d(std::numeric_limits<double>::quiet_NaN(), 0, 0);  // skipped
    }
    RiskParams prm;
    prm.keep_jacobians = true;
    const Vec3d origin(0.1, -0.2, 0.05);
    for (size_t n : {size_t(63), size_t(64), size_t(65), size_t(129), base.size()}) {
        const std::vector<Correspondence> cs(base.begin(), base.begin() + static_cast<long>(n));
        const auto all = computeAlignmentRisk(cs, T, origin, prm);
        size_t skipped = 0;
        Vec6d counts = Vec6d::Zero();
        for (size_t i = 0; i < n; ++i) {
            const auto one = computeAlignmentRisk({cs[i]}, T, origin, prm);
            EXPECT_EQ(all.translation_label[i], one.translation_label[0]) << n << " " << i;
            EXPECT_EQ(all.rotation_label[i], one.rotation_label[0]) << n << " " << i;
            EXPECT_EQ(all.rotation_label2[i], one.rotation_label2[0]) << n << " " << i;
            for (int k = 0; k < 6; ++k) EXPECT_EQ(all.jacobians[i][k], one.jacobians[0][k]) << n << " " << i;
            skipped += one.skipped;
            counts += one.counts;
        }
        EXPECT_EQ(all.skipped, skipped) << n;
        EXPECT_GT(skipped, 0u) << n;
        for (int k = 0; k < 6; ++k) EXPECT_NEAR(all.counts[k], counts[k], 1e-9 * (1 + counts[k])) << n << " " << k;
    }
}

// A 12 x 9 x 3 m room, sensor off-centre: nothing degenerate, and a well-conditioned Hessian.
TEST_P(SceneTest, BoxRoomHasNoDegenerateAxis) {
    const auto cs = castScene({{0, -4}, {0, 8}, {1, -3.5}, {1, 5.5}, {2, -1.2}, {2, 1.8}});
    const auto r = computeAlignmentRisk(cs, params());
    EXPECT_EQ(degenerateAxes(r), "") << r.gamma.transpose();
    EXPECT_FALSE(r.anyDegenerate());
    EXPECT_GT(r.gamma.minCoeff(), 0.3);
    EXPECT_GT(r.eigenvalues[0], 1.0);
    EXPECT_EQ(r.used_by_type[2], cs.size());
}

// The labels are not rotation-invariant (a property of the paper's method): the same corridor
// turned 90 deg about z is degenerate in y instead.
TEST(AlignmentRisk, AxesFollowTheInputFrame) {
    EXPECT_EQ(flags(castScene({{0, -1.5}, {0, 1.6}, {2, -1.2}, {2, 1.4}})), "y");
}

TEST(AlignmentRisk, ObservabilityColours) {
    EXPECT_EQ(observabilityColor(0), (std::array<uint8_t, 3>{255, 0, 0}));
    EXPECT_EQ(observabilityColor(1), (std::array<uint8_t, 3>{0, 255, 0}));
    EXPECT_EQ(observabilityColor(2), (std::array<uint8_t, 3>{0, 0, 255}));
    EXPECT_EQ(observabilityColor(kNoLabel), (std::array<uint8_t, 3>{128, 128, 128}));
}

TEST(RiskParams, LoadsValidatesAndSaves) {
    mrpt::config::CConfigFileMemory c(
        "[risk]\ndegenerate_threshold = 0.25\nweighted_labels=false\n");
    const auto p = loadParams<RiskParams>(c, "risk", "t.ini");
    EXPECT_DOUBLE_EQ(p.degenerate_threshold, 0.25);
    EXPECT_FALSE(p.weighted_labels);
    mrpt::config::CConfigFileMemory bad("[risk]\ndegenerate_threshold = 1.5\n");
    EXPECT_THROW(loadParams<RiskParams>(bad, "risk", "t.ini"), ConfigError);
    mrpt::config::CConfigFileMemory bad3("[risk]\nrotation_labels = 3\n");
    EXPECT_THROW(loadParams<RiskParams>(bad3, "risk", "t.ini"), ConfigError);
    mrpt::config::CConfigFileMemory typo("[risk]\ndegenerate_treshold = 0.2\n");
    EXPECT_THROW(loadParams<RiskParams>(typo, "risk", "t.ini"), ConfigError);
    mrpt::config::CConfigFileMemory out;
    RiskParams{}.saveToConfigFile(out, "risk");
    // What saveToConfigFile writes (padded, commented) loads back through the strict loader.
    out.write("risk", "degenerate_threshold", "0.3");
    EXPECT_DOUBLE_EQ(loadParams<RiskParams>(out, "risk", "saved").degenerate_threshold, 0.3);
}
