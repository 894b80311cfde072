// NEES / ANEES of a pose covariance against ground truth (eval::consistency, doc/evaluation.md).
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/eval/evaluation.h>

#include <random>

using namespace superloc;
using namespace superloc::eval;

namespace {
/// 2000 frames whose errors are drawn from the covariance C (6 x 6, ROS convention: map
/// position, rotation about the map's axes); the frame log carries `C_logged`.
void makeRun(const Mat6d& C, const Mat6d& C_logged, Trajectory& est, Trajectory& gt, FrameLog& log) {
    std::mt19937 rng(3);
    std::normal_distribution<double> n(0.0, 1.0);
    const Eigen::LLT<Mat6d> llt(C);
    const Mat6d L = llt.matrixL();
    for (int i = 0; i < 2000; ++i) {
        PoseStamped g;
        g.t = 0.1 * i;
        g.pose = makePoseRPY(0.5 * i, 2.0, 0.3, 0.01 * i, 0.02, 0.003 * i);
        Vec6d z;
        for (int k = 0; k < 6; ++k) z[k] = n(rng);
        const Vec6d e = L * z;
        PoseStamped s = g;
        s.pose.translation() += e.head<3>();
        s.pose.linear() = expSO3(e.tail<3>()) * g.pose.linear();
        est.push_back(s);
        gt.push_back(g);
        FrameRecord f;
        f.t = g.t;
        f.health = "ok";
        f.cov_pos = C_logged.topLeftCorner<3, 3>();
        f.sigma_rot_deg = Vec3d::Zero();  // unused with the 6 x 6
        f.cov6 = C_logged;
        log.frames.push_back(f);
    }
    log.has_cov = log.has_cov6 = true;
}
}  // namespace

// A covariance that is right gives ANEES near the dof (3, 3, 6) and about 95 % under the
// chi-square 95 % bounds; one 3x too small in variance gives ANEES near 3 x dof.
TEST(Consistency, KnownCovarianceGivesTheDof) {
    Mat6d A = Mat6d::Random();
    Mat6d C = 1e-4 * (A * A.transpose() + Mat6d::Identity());
    Trajectory est, gt;
    FrameLog log;
    makeRun(C, C, est, gt, log);
    const Consistency c = consistency(est, gt, log, 0.02);
    ASSERT_EQ(c.frames(), 2000u);
    ASSERT_TRUE(c.full);
    EXPECT_NEAR(c.anees_pos, 3.0, 0.25);
    EXPECT_NEAR(c.anees_rot, 3.0, 0.25);
    EXPECT_NEAR(c.anees_pose, 6.0, 0.4);
    EXPECT_NEAR(c.under95_pos, 0.95, 0.02);
    EXPECT_NEAR(c.under95_pose, 0.95, 0.02);

    Trajectory est2, gt2;
    FrameLog over;
    makeRun(C, C / 3.0, est2, gt2, over);
    const Consistency o = consistency(est2, gt2, over, 0.02);
    EXPECT_NEAR(o.anees_pos, 9.0, 0.8);
    EXPECT_LT(o.under95_pos, 0.8);
}

// Lost frames and frames without a GT pose are not counted; without the 6 x 6 the rotation is
// read from the diagonal stds about the pose's own axes.
TEST(Consistency, SkipsLostFramesAndReadsTheDiagonalWithoutTheFullCovariance) {
    Mat6d C = Mat6d::Zero();
    C.diagonal() << 4e-4, 1e-4, 1e-4, 1e-6, 1e-6, 4e-6;
    Trajectory est, gt;
    FrameLog log;
    makeRun(C, C, est, gt, log);
    for (auto& f : log.frames) {
        f.cov6.reset();
        // About the pose's own axes: the map's turned by the pose's rotation (diagonal only
        // when the two agree: the rotation errors here are small and about the map's axes).
        const Mat3d R = est[&f - &log.frames[0]].pose.linear();
        const Mat3d Cr = R.transpose() * C.bottomRightCorner<3, 3>() * R;
        f.sigma_rot_deg = Cr.diagonal().cwiseSqrt() / kDeg;
    }
    log.has_cov6 = false;
    log.frames[0].health = "lost";
    const Consistency c = consistency(est, gt, log, 0.02);
    EXPECT_EQ(c.frames(), 1999u);
    EXPECT_FALSE(c.full);
    EXPECT_TRUE(c.pose.empty());
    EXPECT_NEAR(c.anees_pos, 3.0, 0.25);
    EXPECT_NEAR(c.anees_rot, 3.0, 0.6);  // off-diagonal terms of the turned covariance left out
}
