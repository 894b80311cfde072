// The estimate's information without odom_alt and where it is weak (doc/method.md §2).
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/fusion/estimate_information.h>
#include <superloc/fusion/pose_posterior.h>
#include <superloc/fusion/prior_weight.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <iostream>
#include <random>

using namespace superloc;
using namespace superloc::fusion;

namespace {
/// Correspondences of a corridor along the map's x axis (walls y = +-1.25, floor, ceiling) seen
/// from a body yawed by `yaw` [rad], plane normals with angular noise `noise` [rad].
std::vector<Correspondence> corridor(double yaw, double noise, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::normal_distribution<double> n(0, 1);
    const Mat3d R = expSO3(Vec3d(0, 0, yaw));  // map from body
    std::vector<Correspondence> out;
    for (int i = 0; i < 2000; ++i) {
        const int s = i % 4;
        Vec3d p_map(30 * u(rng), 1.25 * u(rng), 1.4 + 1.4 * u(rng)), n_map;
        if (s < 2) p_map.y() = s ? 1.25 : -1.25, n_map = Vec3d(0, s ? -1 : 1, 0);
        else p_map.z() = s == 2 ? 0 : 2.8, n_map = Vec3d(0, 0, s == 2 ? 1 : -1);
        Correspondence c;
        c.p = R.transpose() * p_map;
        c.q = c.p;
        c.n = (R.transpose() * n_map + noise * Vec3d(n(rng), n(rng), n(rng))).normalized();
        c.weight = 1;
        out.push_back(c);
    }
    return out;
}

Vec6d weakSigma() {
    Vec6d w;
    w << Vec3d::Constant(0.05), Vec3d::Constant(0.5 * M_PI / 180);
    return w;
}

/// 0.1 s of an IMU at rest reading gravity only (the motion is the states').
imu::Preintegration gravityOnly() {
    imu::Preintegration pre(imu::ImuBias{}, imu::ImuNoise{0.02, 0.002});
    for (int k = 0; k < 20; ++k) pre.integrate(Vec3d(0, 0, 9.81), Vec3d::Zero(), 0.005);
    return pre;
}

/// The state 0.1 s and 0.5 m along body x after `prev` (5 m/s).
FrameState nextAlongX(const FrameState& prev) {
    FrameState cur = prev;
    cur.t = prev.t + 0.1;
    cur.setPose(prev.T_map_imu() * makePoseRPY(0.5, 0, 0, 0, 0, 0));
    return cur;
}

/// The IMU window from `prev` to `cur` through `pre`.
FrameProblemInputs window(FrameState& prev, FrameState& cur, const imu::Preintegration& pre) {
    FrameProblemInputs in;
    in.prev = &prev;
    in.cur = &cur;
    in.imu = &pre;
    return in;
}
}  // namespace

TEST(EstimateInformation, NoiseFloorTakesTheCorridorAxisNotTheWalls) {
    // 3 degrees of normal noise: the full Hessian holds x at ~2 cm per frame where nothing does.
    const double yaw = 2.0 * M_PI / 180;
    const Mat6d H = scanInformation(corridor(yaw, 3.0 * M_PI / 180, 1), SE3d::Identity(), 0.05);
    const Vec3d axis(std::cos(yaw), -std::sin(yaw), 0);  // the corridor in body axes
    EXPECT_GT(axis.dot(H.topLeftCorner<3, 3>() * axis), 1.0 / (0.03 * 0.03));
    const Mat6d E = informationAboveNoise(H, std::pow(std::sin(4.0 * M_PI / 180), 2));
    EXPECT_LT(axis.dot(E.topLeftCorner<3, 3>() * axis), 1.0);  // nothing left along the corridor
    // The walls and the floor keep (nearly) all of theirs, along their own normals.
    const Vec3d wall(std::sin(yaw), std::cos(yaw), 0);
    EXPECT_GT(wall.dot(E.topLeftCorner<3, 3>() * wall), 0.98 * wall.dot(H.topLeftCorner<3, 3>() * wall));
    EXPECT_GT(E(2, 2), 0.98 * H(2, 2));
    const Mat3d Hr = H.bottomRightCorner<3, 3>(), Er = E.bottomRightCorner<3, 3>();
    EXPECT_TRUE(Er.isApprox(Hr));  // no floor on rotation
    // Where the estimate is weak: the corridor's axis, flagged as body x (not y), and G puts a
    // prior along that axis, not along body x.
    const Weakness w = weakness(E, weakSigma());
    EXPECT_TRUE(w.weak[0]);
    for (int k = 1; k < 6; ++k) EXPECT_FALSE(w.weak[k]) << k;
    EXPECT_NEAR((w.G.topLeftCorner<3, 3>() * axis).norm(), 1.0, 1e-3);
    // A held wall: sqrt(share) = sigma / sqrt(sigma^2 + 5 cm^2), a few mm over 5 cm.
    EXPECT_LT((w.G.topLeftCorner<3, 3>() * wall).norm(), 0.1);
    EXPECT_LT(w.sigma[1], 0.005);
    EXPECT_GE(w.sigma[0], 100.0);
    EXPECT_LT(w.sigma[2], 0.005);
}

TEST(EstimateInformation, EndWallHoldsXAboveTheFloor) {
    // A closed end: 5 % of the correspondences on a wall across the corridor (x = -10 m).
    auto c = corridor(0, 1.0 * M_PI / 180, 2);
    for (size_t i = 0; i < c.size(); i += 20) {
        c[i].p = Vec3d(-10, c[i].p.y(), c[i].p.z());
        c[i].n = Vec3d::UnitX();
    }
    const Mat6d E = informationAboveNoise(scanInformation(c, SE3d::Identity(), 0.05), 0.0049);
    const Weakness w = weakness(E, weakSigma());
    for (int k = 0; k < 6; ++k) EXPECT_FALSE(w.weak[k]) << k;
    EXPECT_LT(w.sigma[0], 0.01);
}

TEST(EstimateInformation, ImuWindowCarriesXForAWhileThenLetsGo) {
    // 20 frames of 0.1 s at 5 m/s along x, the IMU reading gravity only; the scan holds all but
    // x. The carried information keeps x known for a few frames, then it is weak; a scan that
    // holds x makes it strong again at once.
    FusionParams params;
    const imu::Preintegration pre = gravityOnly();
    Mat6d scan_no_x = Mat6d::Zero();
    scan_no_x.diagonal() << 0, 1e5, 1e5, 1e6, 1e6, 1e6;
    Mat6d scan_all = scan_no_x;
    scan_all(0, 0) = 1e5;
    EstimateInformation est;
    FrameState prev;
    prev.setVelocity(Vec3d(5, 0, 0));
    Vec6d sigma_first, sigma_last;
    for (int k = 0; k < 20; ++k) {
        FrameState cur = nextAlongX(prev);
        est.predict(window(prev, cur, pre), params);
        const Mat6d& H = k == 0 ? scan_all : scan_no_x;
        const Weakness w = weakness(est.information(H), weakSigma());
        if (k == 1) sigma_first = w.sigma;
        sigma_last = w.sigma;
        est.commit(cur, H);
        prev = cur;
    }
    EXPECT_LT(sigma_first[0], 0.05);  // just after the scan held x: the IMU carries it
    EXPECT_GT(sigma_last[0], 0.05);   // 1.9 s later: weak (10x the simulated IMU's noise)
    EXPECT_LT(sigma_last[1], 0.01);
    EXPECT_GT(sigma_last[0], 2 * sigma_first[0]);
    // Without IMU nothing is carried: the scan alone.
    est.reset();
    FrameProblemInputs none;
    none.prev = &prev;
    none.cur = &prev;
    est.predict(none, params);
    EXPECT_TRUE(est.information(scan_no_x).isApprox(scan_no_x));
}

// The pose's covariance adds the scan as the estimate does (Tracker::posterior passes
// EstimateInformation::scanPart to PosePosterior): a corridor scan whose x share sits just
// above the noise floor, frame after frame, must not teach the covariance the corridor's axis.
// Measured on the simulated 300 m corridor before: icp + IMU reported x to 2-12 cm while
// 0.3-2 m off.
TEST(EstimateInformation, PoseCovarianceTakesTheScanAsTheEstimateDoes) {
    FusionParams params;
    const imu::Preintegration pre = gravityOnly();
    // The translation block's x share: 0.6 % of its trace, just above sin^2(4 deg) = 0.49 %.
    Mat6d scan = Mat6d::Zero();
    scan.diagonal() << 1.2e3, 1e5, 1e5, 1e6, 1e6, 1e6;
    const double floor_share = std::pow(std::sin(4.0 * M_PI / 180), 2);
    const Mat6d H = informationAboveNoise(scan, floor_share);
    ASSERT_GT(H(0, 0), 0.0);  // above the floor: informationAboveNoise alone keeps some x
    EstimateInformation est;
    PosePosterior with(Vec6d::Zero()), without(Vec6d::Zero());
    FrameState prev;
    prev.setVelocity(Vec3d(5, 0, 0));
    double est_x = 0, with_x = 0, without_x = 0;
    for (int k = 0; k < 100; ++k) {
        FrameState cur = nextAlongX(prev);
        const FrameProblemInputs in = window(prev, cur, pre);
        est.predict(in, params);
        est_x = std::sqrt(cappedCovariance(est.information(H))(0, 0));
        const auto u = with.update(in, params, est.scanPart(H), FloorGeometry{H});
        const auto v = without.update(in, params, H, FloorGeometry{H});
        with_x = std::sqrt(u.cov(0, 0));
        without_x = std::sqrt(v.cov(0, 0));
        with.commit(u);
        without.commit(v);
        est.commit(cur, H);
        prev = cur;
    }
    // 10 s without a real x constraint: the estimate's x std has grown past a metre; the pose's
    // covariance says the same, where the crumbs above the floor would hold it at centimetres.
    std::cout << "x std after 10 s: estimate " << est_x << " m, pose covariance " << with_x
              << " m (with every crumb above the floor: " << without_x << " m)\n";
    EXPECT_GT(est_x, 1.0);
    EXPECT_NEAR(with_x, est_x, 0.05 * est_x);
    EXPECT_LT(without_x, 0.2 * est_x);
}

// The information of an estimate that weighed odom_alt above what it is worth
// (imuWindowStateInformationWeighed, the baselines' covariance): with the weight right it is
// the window's own information; with odom_alt weighed at 1 mm per frame while it is worth 10 cm,
// the estimate follows odom_alt, and along x its position is no surer than odom_alt's 10 cm
// added to what was carried, where the optimal weighting would have kept the IMU's share and
// the claimed weight would say the carried 2 cm.
TEST(EstimateInformation, AnOverweightedOdometryGivesTheEstimateItsOwnError) {
    const imu::Preintegration pre = gravityOnly();
    FrameState prev;
    prev.setVelocity(Vec3d(5, 0, 0));
    FrameState cur = nextAlongX(prev);
    FrameProblemInputs in = window(prev, cur, pre);
    FusionParams params;
    RelativePosePrior p;
    p.delta = prev.T_map_imu().inverse() * cur.T_map_imu();
    const Vec6d worth = Vec6d::Constant(1.0 / (0.1 * 0.1));  // 10 cm / 0.1 rad per frame
    p.sqrt_info = sqrtInfo(Mat6d(worth.asDiagonal()));
    in.prior = p;
    const auto right = imuWindowStateInformation(in, params);
    // The scan inside the sandwich is the scan added after it, when every weight is its worth.
    Mat6d H = Mat6d::Identity() * 1e4;
    H(0, 0) = 10.0;  // a corridor: x barely held
    const auto same = imuWindowStateInformationWeighed(in, params, Mat6d(worth.asDiagonal()), H);
    ASSERT_TRUE(right && same);
    EXPECT_LT((*right - same->without_scan).norm(), 1e-6 * right->norm());
    Mat15d added = *right;
    added.topLeftCorner<6, 6>() += H;
    EXPECT_LT((added - same->with_scan).norm(), 1e-6 * added.norm());
    // Weighed at 1 mm per frame (B_s = 1e6), worth 10 cm.
    in.prior->sqrt_info = sqrtInfo(Mat6d(Vec6d::Constant(1e6).asDiagonal()));
    Mat6d Hx = Mat6d::Zero();
    Hx(0, 0) = 1e4;  // below: a scan that holds x to 1 cm
    const auto weighed = imuWindowStateInformationWeighed(in, params, Mat6d(worth.asDiagonal()), Hx);
    const auto claimed = imuWindowStateInformation(in, params);  // as if odom_alt were 1 mm
    ASSERT_TRUE(weighed && claimed);
    const Mat15d* over = &weighed->without_scan;
    const Mat15d* over_scan = &weighed->with_scan;
    const auto pose = [](const Mat15d& M) { return Mat6d(poseInformation(M).value()); };
    const double sx_opt = std::sqrt(pose(*right).inverse()(0, 0));
    const double sx_over = std::sqrt(pose(*over).inverse()(0, 0));
    const double sx_claimed = std::sqrt(pose(*claimed).inverse()(0, 0));
    const double sx_prev = params.prev_pose_sigma_xyz;  // what was carried (fixed prior)
    EXPECT_NEAR(sx_claimed, std::hypot(sx_prev, 0.001), 0.001);  // the carried x and the claimed 1 mm
    EXPECT_LT(sx_opt, 0.6 * sx_over);  // measured 0.049 against 0.102
    // Following odom_alt: the carried x and odom_alt's 10 cm, within 5 %.
    EXPECT_NEAR(sx_over, std::hypot(sx_prev, 0.1), 0.05 * std::hypot(sx_prev, 0.1));
    // A scan that holds x to 1 cm, weighed by the same solve: the stiff odom_alt drags the
    // previous pose along, so the scan still pulls the estimate, but the estimate mixes in a
    // share of odom_alt's error (its weight against the carried 2 cm): x lands between the
    // scan added to the sandwich afterwards (as if the scan had been weighed optimally against
    // it) and odom_alt's own. Measured: 0.022 m, against 0.0089 m and 0.102 m.
    Mat15d after = *over;
    after.topLeftCorner<6, 6>() += Hx;
    const double sx_after = std::sqrt(pose(after).inverse()(0, 0));
    const double sx_inside = std::sqrt(pose(*over_scan).inverse()(0, 0));
    EXPECT_GT(sx_inside, 2.0 * sx_after);
    EXPECT_LT(sx_inside, 0.5 * sx_over);
    // 0.8 of the scan's 1 cm and 0.2 of the carried 2 cm with odom_alt's 10 cm (weights 1e4 : 2500).
    EXPECT_NEAR(sx_inside, std::sqrt(0.64e-4 + 0.04 * (sx_prev * sx_prev + 0.01)), 0.002);
    std::cout << "x sigma: optimal " << sx_opt << " m, as weighed " << sx_over << " m, as claimed " << sx_claimed
              << " m\n";
}

// Leaving a scan's say along one direction out: withoutDirection is the Schur complement (what
// the scan says of the rest when the pose is free along u), which is below H and says nothing
// along u. The direction must be the carried one (a corridor's axis: body x mixed with z by the
// body's pitch), not the body axis nearest it: with x alone left free, the floor's hold on z
// still pins the axis through the carried correlation.
TEST(PosePosterior, WithoutDirectionIsBelowTheScanAndSaysNothingAlongIt) {
    // A corridor pitched 1 deg in body axes: the scan holds everything but v, plus crumbs along
    // body x (2 cm: an alias, as the end wall's).
    const double p = 1.0 * kDeg;
    Vec6d v = Vec6d::Zero();
    v << std::cos(p), 0, std::sin(p), 0, 0, 0;
    const Mat6d Q = Mat6d::Identity() - v * v.transpose();
    Mat6d H = Q * (Mat6d::Identity() * 1e6) * Q;
    H(0, 0) += 2500;
    const Mat6d W = withoutDirection(H, v);
    EXPECT_LT((W * v).norm(), 1e-6 * H.norm());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat6d>(H - W).eigenvalues().minCoeff(), -1e-6 * H.norm());
    // The posterior along v: carried 2 m there, 1 cm elsewhere. The whole scan collapses it to
    // its crumbs; without the scan's say along v it stays the carried 2 m.
    const Mat6d carried = Q * (Mat6d::Identity() * 1e4) * Q + v * v.transpose() / 4.0;
    const auto sigma_v = [&](const Mat6d& info) { return std::sqrt(v.dot(cappedCovariance(info) * v)); };
    EXPECT_LT(sigma_v(carried + H), 0.03);
    EXPECT_NEAR(sigma_v(carried + W), 2.0, 0.01);
    // Body x left free instead (its Schur complement, or its row and column zeroed): the floor's
    // z, through the carried 1 cm across v, still claims v to half a metre.
    const Vec6d ex = Vec6d::Unit(0);
    Mat6d P = Mat6d::Identity();
    P(0, 0) = 0;
    EXPECT_LT(sigma_v(carried + withoutDirection(H, ex)), 0.7);
    EXPECT_LT(sigma_v(carried + P * H * P), 0.7);
}

// When the frame's scan is not taken along its most uncertain direction (beyondReach): the
// carried position is uncertain there beyond a third of the association's reach, and the risk
// says the scan does not hold the body axis nearest it.
TEST(PosePosterior, BeyondTheAssociationsReachTheScanIsNotTakenAlongTheUnheldAxis) {
    const double p = 1.0 * kDeg;
    Vec6d v = Vec6d::Zero();
    v << std::cos(p), 0, std::sin(p), 0, 0, 0;
    const Mat6d Q = Mat6d::Identity() - v * v.transpose();
    const auto carriedWith = [&](double sigma) { return Mat6d(Q * (Mat6d::Identity() * 1e4) * Q + v * v.transpose() / (sigma * sigma)); };
    Vec6d gamma = Vec6d::Ones();
    gamma[0] = 0.02;  // the corridor's axis
    const double reach = 1.0 / 3.0, weak = 0.3;
    const auto u = beyondReach(carriedWith(2.0), gamma, weak, reach);
    ASSERT_TRUE(u.has_value());
    EXPECT_NEAR(std::abs(u->dot(v)), 1.0, 1e-6);
    EXPECT_FALSE(beyondReach(carriedWith(0.2), gamma, weak, reach).has_value());  // within reach
    gamma[0] = 0.5;
    EXPECT_FALSE(beyondReach(carriedWith(2.0), gamma, weak, reach).has_value());  // the scan holds it
    gamma[0] = 0.02;
    EXPECT_FALSE(beyondReach(Mat6d::Zero(), gamma, weak, reach).has_value());  // nothing carried
}
