// odom_alt drifts as its INI says: drift_per_m metres per metre along a straight path, and
// drift_per_rad radians per radian turned (within 20 %).
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/io/rawlog.h>
#include <superloc/sim/odom_alt.h>

#include "sim_test_utils.h"

using namespace superloc;
using namespace superloc::sim;
using namespace superloc::app;

namespace {

struct Segments {
    double trans_err = 0, dist = 0, rot_err = 0, angle = 0;
};

// Relative-pose errors over consecutive windows of `window` samples, accumulated.
Segments measure(const SmoothTrajectory& tr, const OdomAltParams& p, uint64_t seed, size_t window) {
    OdomAltSimulator sim(p, seed);
    std::vector<SE3d> gt, od;
    for (double t = tr.startTime(); t <= tr.endTime(); t += 1.0 / p.rate_hz) {
        gt.push_back(tr.pose(t));
        od.push_back(sim.step(t, gt.back()).pose);
    }
    Segments s;
    for (size_t i = 0; i + window < gt.size(); i += window) {
        const SE3d dg = gt[i].inverse() * gt[i + window], dd = od[i].inverse() * od[i + window];
        s.trans_err += (dg.translation() - dd.translation()).norm();
        s.dist += dg.translation().norm();
        s.rot_err += logSO3(dg.linear().transpose() * dd.linear()).norm();
        s.angle += logSO3(dg.linear()).norm();
    }
    return s;
}

SmoothTrajectory makeTrajectory(const std::vector<Waypoint>& route, double duration) {
    TrajectoryParams tp;
    tp.max_speed = 2.0;
    tp.max_yaw_rate_deg = 60;
    tp.corner_radius = 0.5;
    return SmoothTrajectory(makeDensePath(route, tp.limits()), tp, 1000.0, duration);
}

}  // namespace

TEST(OdomAlt, TranslationDriftPerMetreMatchesIni) {
    const SmoothTrajectory tr = makeTrajectory({{{0, 0, 0}, 1.0}, {{200, 0, 0}, 1.0}}, 90);
    for (const double drift : {0.01, 0.05}) {
        OdomAltParams p;
        p.drift_per_m = drift;
        for (uint64_t seed : {1, 2, 3}) {
            const Segments s = measure(tr, p, seed, 100);  // 5 s windows, ~10 m
            ASSERT_GT(s.dist, 100.0);
            EXPECT_NEAR(s.trans_err / s.dist, drift, 0.2 * drift) << "seed " << seed;
        }
    }
}

TEST(OdomAlt, RotationDriftPerRadianMatchesIni) {
    std::vector<Waypoint> circle;  // r = 6 m, several laps
    for (int k = 0; k <= 200; ++k)
        circle.push_back({{6 * std::cos(k * 0.3), 6 * std::sin(k * 0.3), 0}, 1.0});
    const SmoothTrajectory tr = makeTrajectory(circle, 60);
    for (const double drift : {0.01, 0.05}) {
        OdomAltParams p;
        p.drift_per_rad = drift;
        p.drift_per_m = 0;
        for (uint64_t seed : {1, 2}) {
            const Segments s = measure(tr, p, seed, 100);  // 5 s windows, ~1.7 rad
            ASSERT_GT(s.angle, 10.0);
            EXPECT_NEAR(s.rot_err / s.angle, drift, 0.2 * drift) << "seed " << seed;
        }
    }
}

TEST(OdomAlt, FirstPoseIsTheOdometryOriginAndCovarianceGrows) {
    const SmoothTrajectory tr = makeTrajectory({{{0, 0, 0}, 1.0}, {{50, 0, 0}, 1.0}}, 20);
    OdomAltSimulator sim(OdomAltParams{}, 1);
    const PoseStamped first = sim.step(tr.startTime(), tr.pose(tr.startTime()));
    EXPECT_TRUE(first.pose.isApprox(SE3d::Identity()));
    PoseStamped last;
    for (double t = tr.startTime() + 0.05; t < tr.endTime(); t += 0.05)
        last = sim.step(t, tr.pose(t));
    ASSERT_TRUE(first.cov && last.cov);
    EXPECT_GT((*last.cov)(0, 0), 100 * (*first.cov)(0, 0));
}

// In the rawlog: odom_alt poses are the body (IMU) frame; their relative motion follows GT
// within the configured drift.
TEST(OdomAlt, RawlogOdometryFollowsBodyMotion) {
    const std::string dir = superloc::testing::freshDir("sim_odom_rawlog");
    const SimConfig cfg = simtest::worldConfig(
        "office",
        {"sim.duration=12", "sim.gt_map_spacing=0.3", "lidar.beams=2", "lidar.columns=32"}, false);
    SimApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    app.initialize(cfg, dir);
    app.run();
    const SimScene scene = makeScene(cfg);
    io::RawlogReader reader(dir + "/sequence.rawlog");
    io::RawlogItem item;
    std::vector<PoseStamped> od;
    while (reader.next(item))
        if (item.kind == io::RawlogItem::Kind::OdomAlt) od.push_back(item.pose());
    ASSERT_EQ(od.size(), static_cast<size_t>(12 * cfg.odom_alt.rate_hz) + 1);
    EXPECT_TRUE(od.front().pose.isApprox(SE3d::Identity(), 1e-6));
    double dist = 0;
    for (size_t i = 1; i < od.size(); ++i)
        dist +=
            translationDistance(scene.trajectory.pose(od[i - 1].t), scene.trajectory.pose(od[i].t));
    const SE3d d_gt =
        scene.trajectory.pose(od.front().t).inverse() * scene.trajectory.pose(od.back().t);
    const SE3d d_od = od.front().pose.inverse() * od.back().pose;
    ASSERT_GT(dist, 5.0);
    // The fixed drift, three sigmas of the wandering per-metre errors, and the heading rate's
    // three sigmas turning the path (half the distance as lever arm).
    const auto& o = cfg.odom_alt;
    const double per_m = o.drift_per_m + 3 * std::hypot(o.scale_sigma, o.lateral_sigma, o.vertical_sigma);
    EXPECT_LT((d_gt.translation() - d_od.translation()).norm(),
              per_m * dist + 1.5 * o.heading_sigma_deg * kDeg * dist * dist + 0.01);
    EXPECT_GT((d_gt.translation() - d_od.translation()).norm(), 0.0);  // it does drift
}

// Jumps: with jump_every = 1 s, jump_xyz = 0.3 m and jump_deg = 2, the increments that hold a
// jump differ from the clean odometry's by exactly 0.3 m and 2 deg (the drift and noise being
// the same: they draw from their own stream), once per second; every other increment is
// identical, and the covariance does not show them.
TEST(OdomAlt, JumpsOncePerPeriodOfTheirSizeAndNothingElseChanges) {
    const SmoothTrajectory tr = makeTrajectory({{{0, 0, 0}, 1.0}, {{30, 0, 0}, 1.0}, {{30, 20, 0}, 1.0}}, 10);
    OdomAltParams jumpy;
    jumpy.jump_every = 1.0;
    jumpy.jump_xyz = 0.3;
    jumpy.jump_deg = 2.0;
    OdomAltSimulator clean(OdomAltParams{}, 4), jumping(jumpy, 4);
    SE3d prev_c, prev_j;
    int jumps = 0, steps = 0;
    for (double t = tr.startTime(); t < tr.endTime(); t += 0.05, ++steps) {
        const PoseStamped c = clean.step(t, tr.pose(t)), j = jumping.step(t, tr.pose(t));
        ASSERT_TRUE(c.cov && j.cov);
        EXPECT_TRUE(c.cov->isApprox(*j.cov));
        if (steps > 0) {
            const SE3d dc = prev_c.inverse() * c.pose, dj = prev_j.inverse() * j.pose;
            const SE3d e = dc.inverse() * dj;  // the jump, if any, in the increment's end frame
            if (e.translation().norm() > 1e-9) {
                ++jumps;
                EXPECT_NEAR(e.translation().norm(), 0.3, 1e-6);
                EXPECT_NEAR(logSO3(e.linear()).norm() / kDeg, 2.0, 1e-6);
            } else {
                EXPECT_LT(logSO3(e.linear()).norm(), 1e-9);
            }
        }
        prev_c = c.pose;
        prev_j = j.pose;
    }
    const double duration = tr.endTime() - tr.startTime();
    EXPECT_NEAR(jumps, std::floor(duration), 1.0);
    OdomAltParams bad;
    bad.jump_xyz = -1;
    EXPECT_THROW(bad.validate(), ConfigError);
}

// drift_axis = x: along a straight path the odometry's position error lies along body x (the
// travel direction, what a corridor's walls do not constrain) at drift_per_m per metre (white
// noise off: its heading random walk alone moves the end point sideways by decimetres).
TEST(OdomAlt, DriftAxisPutsTheDriftOnThatBodyAxis) {
    const SmoothTrajectory tr = makeTrajectory({{{0, 0, 0}, 1.0}, {{100, 0, 0}, 1.0}}, 40);
    OdomAltParams p;
    p.drift_per_m = 0.05;
    p.drift_axis = "x";
    p.trans_noise = 0;
    p.rot_noise_deg = 0;
    for (uint64_t seed : {1, 2}) {
        OdomAltSimulator sim(p, seed);
        SE3d first_gt, first_od, gt, od;
        bool first = true;
        for (double t = tr.startTime(); t <= tr.endTime(); t += 0.05) {
            gt = tr.pose(t);
            od = sim.step(t, gt).pose;
            if (first) first_gt = gt, first_od = od, first = false;
        }
        const SE3d dg = first_gt.inverse() * gt, dd = first_od.inverse() * od;
        const Vec3d err = dd.translation() - dg.translation();  // start frame = body at start
        const double dist = dg.translation().norm();
        ASSERT_GT(dist, 50.0);
        EXPECT_NEAR(std::abs(err.x()), 0.05 * dist, 0.1 * 0.05 * dist) << "seed " << seed;
        EXPECT_LT(std::hypot(err.y(), err.z()), 0.01 * std::abs(err.x())) << "seed " << seed;
    }
    OdomAltParams bad;
    bad.drift_axis = "w";
    EXPECT_THROW(bad.validate(), ConfigError);
}

// Heading slip: every increment turns by slip_deg_per_m per metre about body z more than the
// clean odometry's, so along a straight 40 m path the heading is off by 40 x slip_deg_per_m;
// the covariance does not show it and the translation increments are unchanged.
TEST(OdomAlt, HeadingSlipTurnsYawPerMetreUnreported) {
    const SmoothTrajectory tr = makeTrajectory({{{0, 0, 0}, 1.0}, {{40, 0, 0}, 1.0}}, 30);
    OdomAltParams slipping;
    slipping.slip_deg_per_m = 0.5;
    OdomAltSimulator clean(OdomAltParams{}, 7), slip(slipping, 7);
    SE3d c0, s0, c, s, g0, g;
    bool first = true;
    for (double t = tr.startTime(); t <= tr.endTime(); t += 0.05) {
        g = tr.pose(t);
        const PoseStamped pc = clean.step(t, g), ps = slip.step(t, g);
        ASSERT_TRUE(pc.cov && ps.cov);
        EXPECT_TRUE(pc.cov->isApprox(*ps.cov));
        c = pc.pose;
        s = ps.pose;
        if (first) c0 = c, s0 = s, g0 = g, first = false;
    }
    const double dist = (g0.inverse() * g).translation().norm();
    ASSERT_GT(dist, 35.0);
    const SE3d dc = c0.inverse() * c, ds = s0.inverse() * s;
    const Vec3d e = logSO3(dc.linear().transpose() * ds.linear());
    EXPECT_NEAR(std::abs(e.z()) / kDeg, 0.5 * dist, 0.02 * 0.5 * dist);
    EXPECT_LT(std::hypot(e.x(), e.y()), 0.01 * std::abs(e.z()));
    OdomAltParams bad;
    bad.slip_deg_per_m = -0.1;
    EXPECT_THROW(bad.validate(), ConfigError);
}

// Wandering error: with every sigma 0 the odometry is the fixed-drift one, number for number (its
// own stream); with wander_length = 0 each process is drawn once and held, so along a straight
// path the scale error of every window is the one drawn; with a correlation length L the
// processes are stationary with the INI's sigma and decorrelate over L (pooled over seeds), and
// change_every_m draws them afresh at that distance. None of it is in the covariance.
TEST(OdomAlt, WanderingErrorOffChangesNothing) {
    const SmoothTrajectory tr = makeTrajectory({{{0, 0, 0}, 1.0}, {{30, 0, 0}, 1.0}, {{30, 20, 0}, 1.0}}, 10);
    OdomAltParams wander;
    wander.scale_sigma = 0;
    wander.wander_length = 40;
    wander.change_every_m = 5;
    OdomAltSimulator a(OdomAltParams{}, 9), b(wander, 9);
    for (double t = tr.startTime(); t < tr.endTime(); t += 0.05) {
        const PoseStamped pa = a.step(t, tr.pose(t)), pb = b.step(t, tr.pose(t));
        EXPECT_TRUE(pa.pose.isApprox(pb.pose, 1e-12));
    }
}

TEST(OdomAlt, HeldScaleErrorIsTheDrawnOne) {
    const SmoothTrajectory tr = makeTrajectory({{{0, 0, 0}, 1.0}, {{150, 0, 0}, 1.0}}, 80);
    OdomAltParams p;
    p.drift_per_m = 0;
    p.drift_per_rad = 0;
    p.trans_noise = 0;
    p.rot_noise_deg = 0;
    p.scale_sigma = 0.03;
    for (uint64_t seed : {1, 2, 3}) {
        OdomAltSimulator sim(p, seed);
        SE3d g0, o0, g, o;
        bool first = true;
        for (double t = tr.startTime(); t <= tr.endTime(); t += 0.05) {
            g = tr.pose(t);
            o = sim.step(t, g).pose;
            if (first) g0 = g, o0 = o, first = false;
        }
        const double s = sim.wander()[0];
        EXPECT_NE(s, 0.0);
        const SE3d dg = g0.inverse() * g, dd = o0.inverse() * o;
        const double dist = dg.translation().norm();
        ASSERT_GT(dist, 100.0);
        EXPECT_NEAR(dd.translation().x() - dg.translation().x(), s * dist, 1e-3 * dist) << "seed " << seed;
        EXPECT_NEAR(dd.translation().y() - dg.translation().y(), 0.0, 1e-3 * dist) << "seed " << seed;
    }
}

TEST(OdomAlt, WanderingErrorIsStationaryAndDecorrelatesOverItsLength) {
    // The process itself, stepped along a 2 km straight path in 0.1 m increments, 40 seeds.
    OdomAltParams p;
    p.scale_sigma = 0.02;
    p.lateral_sigma = 0.01;
    p.heading_sigma_deg = 0.1;
    p.wander_length = 40;
    double var = 0, lat = 0, cov40 = 0, cov200 = 0;
    int n = 0, n40 = 0, n200 = 0;
    for (uint64_t seed = 1; seed <= 40; ++seed) {
        OdomAltSimulator sim(p, seed);
        std::vector<double> s;
        SE3d T = SE3d::Identity();
        for (int i = 0; i <= 20000; ++i) {
            T.translation().x() = 0.1 * i;
            sim.step(0.05 * i, T);
            s.push_back(sim.wander()[0]);
            if (i % 100 == 0) {
                var += s.back() * s.back();
                lat += sim.wander()[1] * sim.wander()[1];
                ++n;
            }
        }
        for (size_t i = 0; i + 2000 < s.size(); i += 100) {
            cov40 += s[i] * s[i + 400];  // 40 m apart
            cov200 += s[i] * s[i + 2000];  // 200 m apart
            ++n40;
            ++n200;
        }
    }
    const double sd = std::sqrt(var / n);
    EXPECT_NEAR(sd, 0.02, 0.004);
    EXPECT_NEAR(std::sqrt(lat / n), 0.01, 0.002);
    // Correlation exp(-1) = 0.37 at one length, exp(-5) = 0.007 at five.
    EXPECT_NEAR(cov40 / n40 / (sd * sd), std::exp(-1.0), 0.12);
    EXPECT_NEAR(cov200 / n200 / (sd * sd), 0.0, 0.12);
}

TEST(OdomAlt, AbruptChangesDrawTheErrorAfreshEveryNMetres) {
    OdomAltParams p;
    p.scale_sigma = 0.02;
    p.change_every_m = 10;  // held between changes (wander_length 0)
    OdomAltSimulator sim(p, 5);
    SE3d T = SE3d::Identity();
    double last = 0;
    int changes = 0;
    for (int i = 0; i <= 1000; ++i) {  // 100 m in 0.1 m steps
        T.translation().x() = 0.1 * i;
        const PoseStamped o = sim.step(0.05 * i, T);
        ASSERT_TRUE(o.cov.has_value());
        EXPECT_LT(o.cov->diagonal().head<3>().maxCoeff(), std::pow(0.02 * 0.1 * i + 0.0005 * std::sqrt(i + 1.0) + 1e-4, 2) + 1e-8);
        if (i > 0 && sim.wander()[0] != last) ++changes;
        last = sim.wander()[0];
    }
    EXPECT_NEAR(changes, 10, 1);
    OdomAltParams bad;
    bad.wander_length = -1;
    EXPECT_THROW(bad.validate(), ConfigError);
}
