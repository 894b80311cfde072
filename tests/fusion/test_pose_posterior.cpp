// The reported pose's covariance (fusion::PosePosterior, doc/method.md §4).
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/fusion/pose_posterior.h>
#include <superloc/fusion/prior_weight.h>

#include <Eigen/Eigenvalues>

using namespace superloc;
using namespace superloc::fusion;

// The Jacobian of the relative-pose residual w.r.t. the previous pose, against finite
// differences of toVec6(delta^-1 (T_prev Exp(a))^-1 T_cur) with the right perturbation the
// residuals use (translation in body axes, rotation vector).
TEST(PosePosterior, RelativeJacobianMatchesFiniteDifferences) {
    const SE3d Tp = makePoseRPY(1.0, -2.0, 0.5, 0.1, -0.2, 0.7), Tc = makePoseRPY(1.4, -1.7, 0.45, 0.12, -0.15, 0.9);
    const SE3d delta = Tp.inverse() * Tc;  // zero residual
    const Mat6d J = relativeJacobianPrev(delta);
    const double h = 1e-6;
    for (int j = 0; j < 6; ++j) {
        Vec6d a = Vec6d::Zero();
        a[j] = h;
        SE3d P = Tp;
        P.translation() += Tp.linear() * a.head<3>();
        P.linear() = Tp.linear() * expSO3(a.tail<3>());
        const Vec6d e = toVec6(delta.inverse() * (P.inverse() * Tc));
        for (int i = 0; i < 6; ++i) EXPECT_NEAR(e[i] / h, J(i, j), 1e-4) << i << "," << j;
    }
}

// Without IMU the pose is carried through odom_alt's relative prior alone: with the scan holding
// everything but x, x's variance after N frames is the start's plus N times the prior's, plus
// the floor; the held axes stay at the scan's.
TEST(PosePosterior, WithoutImuTheVarianceAddsUpAlongTheChain) {
    Vec6d floor;
    floor << 0.01, 0.01, 0.01, 0.001, 0.001, 0.001;
    PosePosterior post(floor);
    Mat6d H = Mat6d::Identity() * 1e6;  // the scan: 1 mm everywhere...
    H(0, 0) = 0;                        // ...but along x
    FusionParams params;
    FrameState prev, cur;
    // The first frame: the scan alone, and a start 5 cm along x given by hand.
    Mat6d H0 = H;
    H0(0, 0) = 1.0 / (0.05 * 0.05);
    prev.setPose(SE3d::Identity());
    FrameProblemInputs in0;
    in0.cur = &prev;
    auto u = post.update(in0, params, H0);
    post.commit(u);
    EXPECT_NEAR(u.cov(0, 0), 0.05 * 0.05 + 0.01 * 0.01, 1e-8);
    const double sf = 0.02;  // odom_alt's std per frame along x
    for (int k = 1; k <= 50; ++k) {
        cur.setPose(makePoseRPY(0.5 * k, 0, 0, 0, 0, 0));
        RelativePosePrior p;
        p.delta = prev.T_map_imu().inverse() * cur.T_map_imu();
        Vec6d w;
        w << 1 / (sf * sf), 1e4, 1e4, 1e6, 1e6, 1e6;
        p.sqrt_info = sqrtInfo(w);
        FrameProblemInputs in;
        in.prev = &prev;
        in.cur = &cur;
        in.prior = p;
        u = post.update(in, params, H);
        post.commit(u);
        prev = cur;
    }
    EXPECT_NEAR(u.cov(0, 0), 0.05 * 0.05 + 50 * sf * sf + 0.01 * 0.01, 0.02 * u.cov(0, 0));
    EXPECT_LT(u.cov(1, 1), 0.01 * 0.01 + 1e-5);
    // Symmetric positive definite.
    EXPECT_TRUE(u.cov.isApprox(u.cov.transpose(), 1e-12));
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat6d>(u.cov).eigenvalues().minCoeff(), 0.0);
    // A reset forgets: the next frame's x is the scan's alone (unheld: capped at 1 km).
    post.reset();
    FrameProblemInputs alone;
    alone.cur = &cur;
    u = post.update(alone, params, H);
    EXPECT_GT(std::sqrt(u.cov(0, 0)), 100.0);
}

// toReported: the ROS convention of the reported pose (position in the map, rotation about the
// map's axes). A body turned 90 deg in yaw has its body-x variance on the map's y; a lever arm
// turns rotation uncertainty into position uncertainty at the reported frame.
TEST(PosePosterior, ReportedCovarianceIsInTheMapFrameOfTheReportedPose) {
    Mat6d C = Mat6d::Zero();
    C.diagonal() << 0.04, 0.0001, 0.0001, 1e-6, 1e-6, 1e-4;
    const SE3d T = makePoseRPY(3, 4, 0, 0, 0, M_PI / 2);
    const Mat6d R0 = toReported(C, T, SE3d::Identity());
    EXPECT_NEAR(R0(1, 1), 0.04, 1e-12);
    EXPECT_NEAR(R0(0, 0), 0.0001, 1e-12);
    EXPECT_NEAR(R0(5, 5), 1e-4, 1e-12);
    const Mat6d R1 = toReported(C, T, makePoseRPY(1.0, 0, 0, 0, 0, 0));  // 1 m ahead along body x
    // yaw's 0.01 rad moves the point 1 m ahead by 1 cm across the body: along the map's x.
    EXPECT_NEAR(R1(0, 0), 0.0001 + 1e-4 * 1.0, 1e-9);
}
