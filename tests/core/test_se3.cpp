#include <gtest/gtest.h>
#include <superloc/core/mrpt_conversions.h>
#include <superloc/core/se3.h>

#include <cmath>
#include <vector>

using namespace superloc;

TEST(SE3, ExpLogRoundTripIncludingNearPi) {
    for (const Vec3d& phi : std::vector<Vec3d> {Vec3d(0, 0, 0), Vec3d(1e-9, 0, 0), Vec3d(0.3, -0.2, 0.1),
                            Vec3d(0, 0, M_PI - 1e-6), Vec3d(Vec3d(1.0, 2.0, -0.5).normalized() * 3.0)}) {
        const Vec3d back = logSO3(expSO3(phi));
        EXPECT_LT((expSO3(back) - expSO3(phi)).norm(), 1e-9) << phi.transpose();
        if (phi.norm() < M_PI - 1e-3) {
            EXPECT_LT((back - phi).norm(), 1e-9);
        }
    }
}

TEST(SE3, RightJacobianMatchesFiniteDifference) {
    // Exp(phi + d) ~= Exp(phi) Exp(Jr(phi) d)
    const Vec3d phi(0.4, -0.7, 0.2), d(1e-6, -2e-6, 1.5e-6);
    const Mat3d lhs = expSO3(phi + d);
    const Mat3d rhs = expSO3(phi) * expSO3(rightJacobianSO3(phi) * d);
    EXPECT_LT((lhs - rhs).norm(), 1e-11);
    EXPECT_LT((rightJacobianSO3(phi) * rightJacobianInvSO3(phi) - Mat3d::Identity()).norm(), 1e-12);
}

TEST(SE3, InterpolateAtBracketsAndRejectsGaps) {
    Trajectory traj = {{0.0, makePoseRPY(0, 0, 0, 0, 0, 0), {}},
                       {1.0, makePoseRPY(2, 0, 0, 0, 0, 0.5), {}},
                       {5.0, makePoseRPY(4, 0, 0, 0, 0, 0.5), {}}};
    const auto mid = interpolateAt(traj, 0.5);
    ASSERT_TRUE(mid.has_value());
    EXPECT_NEAR(mid->translation().x(), 1.0, 1e-12);
    EXPECT_NEAR(logSO3(mid->linear()).z(), 0.25, 1e-12);
    EXPECT_FALSE(interpolateAt(traj, -0.1).has_value());
    EXPECT_FALSE(interpolateAt(traj, 3.0, /*max_gap=*/1.0).has_value());
    EXPECT_TRUE(interpolateAt(traj, 3.0, /*max_gap=*/10.0).has_value());
}

TEST(MrptConversions, PoseAndCovarianceOrder) {
    const SE3d T = makePoseRPY(1, 2, 3, 0.1, -0.2, 0.3);
    const mrpt::poses::CPose3D p = toMrpt(T);
    EXPECT_NEAR(p.yaw(), 0.3, 1e-12);
    EXPECT_NEAR(p.pitch(), -0.2, 1e-12);
    EXPECT_NEAR(p.roll(), 0.1, 1e-12);
    EXPECT_LT((toEigen(p).matrix() - T.matrix()).norm(), 1e-12);

    Mat6d c = Mat6d::Zero();
    c.diagonal() << 1, 2, 3, 4, 5, 6;  // x y z roll pitch yaw
    const auto m = covToMrpt(c);       // x y z yaw pitch roll
    EXPECT_EQ(m(3, 3), 6);
    EXPECT_EQ(m(5, 5), 4);
    EXPECT_LT((covFromMrpt(m) - c).norm(), 1e-15);
}

TEST(SE3, TurnedAboutVerticalKeepsTheTranslationAndTurnsTheHeading) {
    const SE3d T = makePoseRPY(1.0, 2.0, 3.0, 0.1, -0.2, 0.3);
    const SE3d U = turnedAboutVertical(T, M_PI / 2);
    EXPECT_TRUE(U.translation().isApprox(T.translation()));
    // The body x axis in the map turns by +90 deg about z: (a, b, c) -> (-b, a, c).
    const Vec3d x0 = T.linear().col(0), x1 = U.linear().col(0);
    EXPECT_NEAR(x1.x(), -x0.y(), 1e-12);
    EXPECT_NEAR(x1.y(), x0.x(), 1e-12);
    EXPECT_NEAR(x1.z(), x0.z(), 1e-12);
    EXPECT_EQ(turnedAboutVertical(T, 0.0).matrix(), T.matrix());  // no turn: bit for bit
}
