// The reported pose's covariance (fusion::PosePosterior, doc/method.md §4).
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/fusion/estimate_information.h>
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
    auto u = post.update(in0, params, H0, FloorGeometry{H0});
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
        u = post.update(in, params, H, FloorGeometry{H});
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
    u = post.update(alone, params, H, FloorGeometry{H});
    EXPECT_GT(std::sqrt(u.cov(0, 0)), 100.0);
}

// A frame whose registration is in doubt reports what it knew without its scan: the scan's
// information is taken at associations that may be wrong (the wander sweep's seed 2: a corridor's
// end wall coming into view 5.4 m from where the drifted pose puts it claimed 1 cm along x, NEES
// ~2e5 on five frames, the run's position ANEES 537 -> 9 without them). Dropped, the scan is not
// carried to the next frame either.
TEST(PosePosterior, AFrameInDoubtKeepsWhatItKnewWithoutItsScan) {
    PosePosterior post(Vec6d::Constant(0.001));
    FusionParams params;
    FrameState prev, cur;
    prev.setPose(SE3d::Identity());
    cur.setPose(makePoseRPY(0.5, 0, 0, 0, 0, 0));
    // Carried: the last pose to 1 m along x, 1 cm elsewhere.
    Mat6d I0 = Mat6d::Identity() * 1e4;
    I0(0, 0) = 1.0;
    FrameProblemInputs first;
    first.cur = &prev;
    post.commit(post.update(first, params, I0, FloorGeometry{I0}));
    RelativePosePrior p;
    p.delta = prev.T_map_imu().inverse() * cur.T_map_imu();
    p.sqrt_info = sqrtInfo(Vec6d(Vec6d::Constant(1e6)));  // the relative motion: 1 mm
    FrameProblemInputs in;
    in.prev = &prev;
    in.cur = &cur;
    in.prior = p;
    const Mat6d H = Mat6d::Identity() * 1e6;  // this frame's scan: 1 mm along everything
    auto u = post.update(in, params, H, FloorGeometry{H});
    EXPECT_LT(std::sqrt(u.cov(0, 0)), 0.002);
    const auto w = post.withoutScan(u);
    EXPECT_NEAR(std::sqrt(w.cov(0, 0)), 1.0, 0.01);  // the carried metre
    EXPECT_NEAR(std::sqrt(w.cov(1, 1)), 0.0112, 0.001);  // 1 cm, and 0.01 rad of yaw over 0.5 m
    EXPECT_LT(std::sqrt(u.cov(0, 0)), 0.002);  // the update itself is untouched
    post.commit(w);
    // The next frame without a scan still carries the metre, not the dropped millimetre.
    FrameState next;
    next.setPose(makePoseRPY(1.0, 0, 0, 0, 0, 0));
    in.prev = &cur;
    in.cur = &next;
    p.delta = cur.T_map_imu().inverse() * next.T_map_imu();
    in.prior = p;
    const auto v = post.update(in, params, Mat6d::Zero(), FloorGeometry{Mat6d::Zero()});
    EXPECT_GT(std::sqrt(v.cov(0, 0)), 0.99);
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

// The map's coherent error turns the pose by map_sigma over the scan's lever arm: in a cube room
// of half-size a (points spread uniformly over the six walls), the torque arm about z is y on the
// x walls and x on the y walls and nothing on floor and ceiling, so 3 H_zz / tr H_tt = 3 (4/6)
// (a^2/3) = 2 a^2 / 3 for every axis. A room twice as large halves the floor; no scan, no floor.
TEST(PosePosterior, MapRotationFloorIsTheMapErrorOverTheScansLeverArm) {
    const auto room = [](double a) {
        std::vector<Correspondence> c;
        const int m = 40;
        for (int axis = 0; axis < 3; ++axis)
            for (int side = -1; side <= 1; side += 2)
                for (int i = 0; i < m; ++i)
                    for (int j = 0; j < m; ++j) {
                        const double u = a * (-1 + (2.0 * i + 1) / m), v = a * (-1 + (2.0 * j + 1) / m);
                        Correspondence k;
                        k.p[axis] = side * a;
                        k.p[(axis + 1) % 3] = u;
                        k.p[(axis + 2) % 3] = v;
                        k.q = k.p;
                        k.n = Vec3d::Zero();
                        k.n[axis] = side;
                        c.push_back(k);
                    }
        return scanInformation(c, SE3d::Identity(), 0.05);
    };
    const double sigma = 0.005;
    const Vec3d f4 = mapRotationFloor(room(4.0), sigma), f8 = mapRotationFloor(room(8.0), sigma);
    const double expected = sigma / (4.0 * std::sqrt(2.0 / 3.0));  // 1.53 mrad = 0.088 deg
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(f4[k], expected, 0.01 * expected) << k;
        EXPECT_NEAR(f8[k], 0.5 * expected, 0.01 * expected) << k;
    }
    EXPECT_EQ(mapRotationFloor(Mat6d::Zero(), sigma), Vec3d::Zero());
    EXPECT_EQ(mapRotationFloor(room(4.0), 0.0), Vec3d::Zero());
    // The posterior's floor: the fixed floor where it is larger, the map's where that is.
    Vec6d fixed;
    fixed << 0.01, 0.01, 0.01, 0.001, 0.001, 0.001;
    const PosePosterior post(fixed, sigma);
    const Vec6d f = post.floor(FloorGeometry{room(4.0)});
    EXPECT_EQ(f.head<3>(), fixed.head<3>());
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(f[3 + k], expected, 0.01 * expected);
    EXPECT_NEAR(post.floor(FloorGeometry{room(40.0)})[3], 0.001, 1e-12);  // a 40 m hall: 0.15 mrad, the fixed floor holds
}

namespace {
Correspondence planePoint(const Vec3d& p, const Vec3d& n, float rel_time) {
    Correspondence c;
    c.p = p;
    c.q = p;
    c.n = n;
    c.type = FeatureType::Plane;
    c.rel_time = rel_time;
    return c;
}
}  // namespace

// A sweep whose points were all taken at one time: the pose is off by that time's share of the
// departure, axis by axis (the per-axis term the sweep's covariance had before its points' times
// were used): a parabola's peak at mid-sweep, half of a rate's error halfway back.
TEST(SweepCovariance, PointsOfOneTimeGiveTheirShareOfTheDepartureAxisByAxis) {
    std::vector<Correspondence> room;
    const double T = 0.1;
    for (int face = 0; face < 6; ++face) {
        const int ax = face / 2;
        const double side = face % 2 ? 1.0 : -1.0;
        Vec3d n = Vec3d::Zero();
        n[ax] = 1.0;
        for (int i = -3; i <= 3; ++i)
            for (int j = -3; j <= 3; ++j) {
                Vec3d p;
                p[ax] = side * 4.0;
                p[(ax + 1) % 3] = 0.9 * i;
                p[(ax + 2) % 3] = 0.7 * j;
                room.push_back(planePoint(p, n, float(-0.5 * T)));
            }
    }
    SweepDeparture d;
    d.delta << 0.01, 0.02, 0.005, 0.001, 0.002, 0.003;
    d.T = T;
    d.parabola = true;  // g(1/2) = 1
    const Mat6d full = sweepCovariance(room, SE3d::Identity(), d, 0.05, 0.0049, Mat6d::Zero());
    d.parabola = false;  // g(1/2) = 1/2
    const Mat6d half = sweepCovariance(room, SE3d::Identity(), d, 0.05, 0.0049, Mat6d::Zero());
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) {
            const double want = i == j ? d.delta[i] * d.delta[i] : 0.0;
            EXPECT_NEAR(full(i, j), want, 1e-6 * d.delta.squaredNorm()) << i << "," << j;
            EXPECT_NEAR(half(i, j), 0.25 * want, 1e-6 * d.delta.squaredNorm()) << i << "," << j;
        }
    d.delta.setZero();
    EXPECT_TRUE(sweepCovariance(room, SE3d::Identity(), d, 0.05, 0.0049, Mat6d::Zero()).isZero());
}

// A corridor's floor seen ahead at mid-sweep and behind at the sweep's ends: a pitch that bends
// over the sweep tilts the floor ahead and leaves the floor behind, and the fit answers with half
// the pitch and a height X / 2 of it the other way (z = -X pitch, X the floor's distance): the
// coupling the corridor without IMU showed (z error following the pitch error at -0.11 m/deg,
// floor ~6 m ahead and behind, doc/results.md), which a per-axis term cannot carry.
TEST(SweepCovariance, FloorAheadAndBehindSeenAtDifferentTimesCouplesHeightWithPitch) {
    const double X = 6.0, T = 0.1;
    std::vector<Correspondence> floor;
    for (int j = -4; j <= 4; ++j) {
        const double y = 0.25 * j;
        floor.push_back(planePoint(Vec3d(X, y, -0.3), Vec3d::UnitZ(), float(-0.5 * T)));  // ahead: mid-sweep
        floor.push_back(planePoint(Vec3d(-X, y, -0.3), Vec3d::UnitZ(), float(-T)));      // behind: first ...
        floor.push_back(planePoint(Vec3d(-X, y, -0.3), Vec3d::UnitZ(), 0.0f));           // ... and last
    }
    // x, y, roll and yaw held by something else (walls, the carried estimate).
    Mat6d carried = Mat6d::Zero();
    for (int k : {0, 1, 3, 5}) carried(k, k) = 1e12;
    SweepDeparture d;
    d.delta[4] = 0.15 * kDeg;  // pitch sway's departure at mid-sweep
    d.T = T;
    d.parabola = true;
    const Mat6d C = sweepCovariance(floor, SE3d::Identity(), d, 0.05, 0.0049, carried);
    const double p2 = std::pow(0.5 * d.delta[4], 2);
    EXPECT_NEAR(C(4, 4), p2, 0.01 * p2) << "half the pitch";
    EXPECT_NEAR(C(2, 4) / C(4, 4), -X, 0.01 * X) << "z = -X pitch";
    EXPECT_NEAR(C(2, 2), X * X * p2, 0.02 * X * X * p2);
    // The same floor seen all at once couples nothing: the scan's own z-pitch information is zero.
    for (auto& c : floor) c.rel_time = float(-0.5 * T);
    const Mat6d once = sweepCovariance(floor, SE3d::Identity(), d, 0.05, 0.0049, carried);
    EXPECT_NEAR(once(2, 2), 0.0, 1e-6 * p2);
    EXPECT_NEAR(once(4, 4), 4.0 * p2, 0.01 * p2);
}

namespace {
/// A box of planes around `centre`, `half` metres to each face, n points per face: it holds all
/// three translations equally.
void addRoom(std::vector<Correspondence>& out, const Vec3d& centre, double half, int n) {
    for (int face = 0; face < 6; ++face) {
        const int axis = face / 2;
        const double sign = face % 2 ? 1.0 : -1.0;
        for (int i = 0; i < n; ++i) {
            Vec3d q = centre;
            q[axis] += sign * half;
            q[(axis + 1) % 3] += half * (2.0 * (i % 7) / 6.0 - 1.0);
            q[(axis + 2) % 3] += half * (2.0 * (i / 7 % 7) / 6.0 - 1.0);
            Vec3d nrm = Vec3d::Zero();
            nrm[axis] = 1.0;
            out.push_back(planePoint(q, nrm, 0.0f));
        }
    }
}
}  // namespace

// A map error coherent over the whole footprint (a correlation length far beyond it) moves the
// pose with it: all of it on every axis. Rooms far apart, beyond the correlation length, err
// independently, and the pose takes the average of K of them: 1/K on every axis.
TEST(MapErrorShare, CoherentFieldIsTakenWholeIndependentRoomsAverageOut) {
    std::vector<Correspondence> one;
    addRoom(one, Vec3d(0, 0, 0), 3.0, 49);
    const Mat3d whole = mapErrorShare(one, SE3d::Identity(), 4.0, 1e6, 1e-6);
    EXPECT_TRUE(whole.isApprox(Mat3d::Identity(), 1e-9)) << whole;
    std::vector<Correspondence> four;
    for (int k = 0; k < 4; ++k) addRoom(four, Vec3d(1000.0 * k, 0, 0), 3.0, 49);
    // A field correlated over 50 m: each 6 m room moves (nearly) as one, the rooms 1 km apart
    // independently (4 rooms at 4 m cells stay well under kMapShareMaxCells).
    const Mat3d apart = mapErrorShare(four, SE3d::Identity(), 4.0, 50.0, 1e-6);
    EXPECT_TRUE(apart.isApprox(0.25 * Mat3d::Identity(), 0.01)) << apart;
    // Within a room that decorrelates over 2 m, the room averages its own faces out.
    EXPECT_LT(mapErrorShare(one, SE3d::Identity(), 1.0, 2.0, 1e-6)(0, 0), 0.9);
    // The same rooms within a correlation length of each other: between the two.
    std::vector<Correspondence> near;
    for (int k = 0; k < 4; ++k) addRoom(near, Vec3d(8.0 * k, 0, 0), 3.0, 49);
    const Mat3d m = mapErrorShare(near, SE3d::Identity(), 4.0, 10.0, 1e-6);
    for (int k = 0; k < 3; ++k) {
        EXPECT_GT(m(k, k), 0.3) << k;
        EXPECT_LT(m(k, k), 0.95) << k;
    }
}

// A corridor's walls and floor do not hold its axis: the map's error along it is taken whole,
// whatever the footprint; across it a 100 m corridor averages a 2 m-correlated error out. The
// share is in body axes: the same corridor seen from a body turned by 90 degrees about z has
// its unheld axis along body y.
TEST(MapErrorShare, AnUnheldAxisTakesAllAHeldOneAveragesInBodyAxes) {
    std::vector<Correspondence> corridor;
    for (int i = 0; i < 400; ++i) {
        const double x = -50.0 + 0.25 * i;
        corridor.push_back(planePoint(Vec3d(x, -1.5, 1.0), Vec3d(0, 1, 0), 0.0f));
        corridor.push_back(planePoint(Vec3d(x, 1.5, 1.0), Vec3d(0, -1, 0), 0.0f));
        corridor.push_back(planePoint(Vec3d(x, 0.0, 0.0), Vec3d(0, 0, 1), 0.0f));
    }
    const Mat3d M = mapErrorShare(corridor, SE3d::Identity(), 4.0, 2.0, 0.01);
    EXPECT_NEAR(M(0, 0), 1.0, 1e-9);
    EXPECT_LT(M(1, 1), 0.2);
    EXPECT_LT(M(2, 2), 0.2);
    EXPECT_GT(M(1, 1), 0.0);
    const SE3d turned = makePoseRPY(0, 0, 0, 0, 0, M_PI / 2);
    const Mat3d B = mapErrorShare(corridor, turned, 4.0, 2.0, 0.01);
    EXPECT_NEAR(B(1, 1), 1.0, 1e-9);
    EXPECT_NEAR(B(0, 0), M(1, 1), 1e-9);
    // Nothing to read it off: all of it.
    EXPECT_TRUE(mapErrorShare({}, SE3d::Identity(), 4.0, 2.0, 0.01).isApprox(Mat3d::Identity()));
    EXPECT_TRUE(mapErrorShare(corridor, SE3d::Identity(), 4.0, 0.0, 0.01).isApprox(Mat3d::Identity()));
}

// A footprint of more cells than kMapShareMaxCells is summed on a coarser grid: still a share
// (symmetric, eigenvalues in [0, 1]) and close to the fine grid's where the cells are well
// within a correlation length.
TEST(MapErrorShare, CoarserGridBeyondTheCellCapStaysAShare) {
    std::vector<Correspondence> field;
    for (int i = 0; i < 60; ++i)
        for (int j = 0; j < 60; ++j) {
            const Vec3d q(-150.0 + 5.0 * i, -150.0 + 5.0 * j, 0.0);
            field.push_back(planePoint(q, Vec3d(0, 0, 1), 0.0f));
            field.push_back(planePoint(q + Vec3d(1, 0, 1), Vec3d(1, 0, 0), 0.0f));
            field.push_back(planePoint(q + Vec3d(0, 1, 1), Vec3d(0, 1, 0), 0.0f));
        }
    const Mat3d M = mapErrorShare(field, SE3d::Identity(), 4.0, 20.0, 1e-6);  // 3 600 cells of 4 m
    const Eigen::SelfAdjointEigenSolver<Mat3d> es(M);
    EXPECT_TRUE(M.isApprox(M.transpose(), 1e-12));
    EXPECT_GE(es.eigenvalues().minCoeff(), 0.0);
    EXPECT_LE(es.eigenvalues().maxCoeff(), 1.0 + 1e-12);
    // A 300 m square of 20 m-correlated error: roughly (20 sqrt(2 pi) / 300)^2 ~ 0.03 of it.
    for (int k = 0; k < 3; ++k) {
        EXPECT_GT(M(k, k), 0.005) << k;
        EXPECT_LT(M(k, k), 0.1) << k;
    }
}

// The floor with a map share: with IMU the position's floor is the map's, shaped by the share;
// without, the rest of the constant floor (deskew, timing) stays on every axis. No share: the
// constant floor, as before.
TEST(MapErrorShare, ShapesThePositionFloorOnly) {
    Vec6d fixed;
    fixed << 0.01, 0.01, 0.01, 0.001, 0.001, 0.001;
    const PosePosterior post(fixed, 0.0, 0.007);
    Mat3d share = Mat3d::Zero();
    share.diagonal() << 1.0, 0.25, 0.04;
    share(0, 1) = share(1, 0) = 0.1;
    const Mat6d with = post.floorCovariance(FloorGeometry{Mat6d::Zero(), true, share});
    EXPECT_TRUE((with.topLeftCorner<3, 3>().isApprox(0.007 * 0.007 * share, 1e-12)));
    EXPECT_TRUE((with.bottomRightCorner<3, 3>().isApprox(Mat3d::Identity() * 1e-6, 1e-12)));
    EXPECT_TRUE((with.topRightCorner<3, 3>().isZero()));
    const Mat6d without = post.floorCovariance(FloorGeometry{Mat6d::Zero(), false, share});
    const Mat3d expected = (0.01 * 0.01 - 0.007 * 0.007) * Mat3d::Identity() + 0.007 * 0.007 * share;
    EXPECT_TRUE((without.topLeftCorner<3, 3>().isApprox(expected, 1e-12)));
    const Mat6d constant = post.floorCovariance(FloorGeometry{Mat6d::Zero(), true, std::nullopt});
    EXPECT_TRUE((constant.topLeftCorner<3, 3>().isApprox(0.007 * 0.007 * Mat3d::Identity(), 1e-12)));
}

// The drift's direction (driftTiltCovariance): a position carried 2 m along a corridor that the
// scan holds to 3 mm across, whose free direction the map's normals tilt by 0.4 deg against the
// axis the pose really drifts along. The error such a drift makes (2 m along the axis, the scan's
// hold across it) is far outside the covariance as linearized, and inside it with the term; the
// term is nothing along the free direction, and nothing where the information leaves a direction
// unheld.
TEST(PosePosterior, TheDriftsDirectionIsKnownToItsTiltOnly) {
    const double tilt = 0.4 * kDeg;
    const Vec3d u(std::cos(tilt), std::sin(tilt), 0.0);  // the linearized free direction
    const Vec3d v(-u.y(), u.x(), 0.0);
    Mat6d C = Mat6d::Identity() * 1e-6;
    C.topLeftCorner<3, 3>() = 4.0 * u * u.transpose() + 9e-6 * (v * v.transpose() + Vec3d::UnitZ() * Vec3d::UnitZ().transpose());
    const Vec3d err(2.0, 0.0, 0.0);  // along the true axis
    const auto nees = [&](const Mat6d& M) { return err.dot(M.topLeftCorner<3, 3>().ldlt().solve(err)); };
    EXPECT_GT(nees(C), 20.0);
    const Mat6d T = driftTiltCovariance(C, 0.5 * kDeg);
    EXPECT_LT(nees(C + T), 7.81);
    EXPECT_NEAR(u.dot(T.topLeftCorner<3, 3>() * u), 0.0, 1e-12);
    EXPECT_NEAR(v.dot(T.topLeftCorner<3, 3>() * v), std::pow(std::sin(0.5 * kDeg) * 2.0, 2), 1e-9);
    EXPECT_TRUE(T.bottomRows<3>().isZero() && T.rightCols<3>().isZero());
    EXPECT_TRUE(driftTiltCovariance(C, 0.0).isZero());
    Mat6d unheld = C;
    unheld.topLeftCorner<3, 3>() += kMaxSigma * kMaxSigma * u * u.transpose();
    EXPECT_TRUE(driftTiltCovariance(unheld, 0.5 * kDeg).isZero());
}
