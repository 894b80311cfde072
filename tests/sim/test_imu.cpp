// Integrating the noise-free IMU from the first GT state reproduces the GT trajectory (10 s,
// 5 cm), in-process for every world and end-to-end through the rawlog; noise has the INI level.
#include <superloc/core/se3.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/tum.h>
#include <superloc/sim/imu_model.h>

#include "sim_test_utils.h"

using namespace superloc;
using namespace superloc::sim;
using namespace superloc::app;

namespace {

struct NavState {
    Mat3d R;
    Vec3d p, v;
};

// Trapezoidal strapdown integration between consecutive samples (second order).
NavState integrate(NavState x, const std::vector<ImuSample>& m, double gravity) {
    const Vec3d g(0, 0, -gravity);
    for (size_t k = 0; k + 1 < m.size(); ++k) {
        const double dt = m[k + 1].t - m[k].t;
        const Mat3d R1 = x.R * expSO3(0.5 * (m[k].gyro + m[k + 1].gyro) * dt);
        const Vec3d a0 = x.R * m[k].acc + g, a1 = R1 * m[k + 1].acc + g;
        x.p += x.v * dt + (2 * a0 + a1) / 6 * dt * dt;
        x.v += 0.5 * (a0 + a1) * dt;
        x.R = R1;
    }
    return x;
}

}  // namespace

TEST(Imu, NoiseFreeIntegrationFollowsGroundTruthInEveryWorld) {
    for (const std::string w : {"corridor", "cave", "multifloor", "openfield", "office"}) {
        SCOPED_TRACE(w);
        const SimConfig cfg = simtest::worldConfig(w, {"sim.duration=40"});
        const SimScene scene = makeScene(cfg);
        const auto& tr = scene.trajectory;
        // From rest at the start, and from a moving state 25 s in.
        for (const double start : {tr.startTime(), tr.startTime() + 25.0}) {
            std::vector<ImuSample> m;
            for (int k = 0; k <= 2000; ++k)
                m.push_back(ImuSimulator::ideal(tr.at(start + k / 200.0), 9.81));
            const BodyState s0 = tr.at(start), s1 = tr.at(start + 10.0);
            const NavState end =
                integrate({s0.T_map_body.linear(), s0.T_map_body.translation(), s0.vel}, m, 9.81);
            EXPECT_LT((end.p - s1.T_map_body.translation()).norm(), 0.05)
                << "start " << start - tr.startTime();
            EXPECT_LT(logSO3(end.R.transpose() * s1.T_map_body.linear()).norm(), 0.2 * M_PI / 180);
        }
    }
}

TEST(Imu, NoiseFreeRawlogIntegratesToGtTum) {
    const std::string dir = superloc::testing::freshDir("sim_imu_rawlog");
    SimConfig cfg = simtest::worldConfig(
        "cave",
        {"sim.duration=10.5", "sim.gt_map_spacing=0.2", "lidar.beams=2", "lidar.columns=32",
         "imu.acc_noise_density=0", "imu.gyro_noise_density=0", "imu.acc_bias_rw=0",
         "imu.gyro_bias_rw=0", "imu.acc_bias_init=0", "imu.gyro_bias_init=0"},
        false);
    SimApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    app.initialize(cfg, dir);
    app.run();

    std::vector<ImuSample> m;
    Trajectory gt;
    io::RawlogReader reader(dir + "/sequence.rawlog");
    io::RawlogItem item;
    SE3d T_imu_lidar = SE3d::Identity();
    while (reader.next(item)) {
        if (item.kind == io::RawlogItem::Kind::Imu) m.push_back(item.imu());
        if (item.kind == io::RawlogItem::Kind::Lidar) T_imu_lidar = item.scan().T_imu_lidar;
    }
    gt = io::loadTum(dir + "/gt_tum.txt");
    ASSERT_GE(m.size(), 2001u);
    ASSERT_GE(gt.size(), 100u);
    // First GT state: the body at the first IMU sample (at rest), from the scene.
    const SimScene scene = makeScene(cfg);
    const BodyState s0 = scene.trajectory.at(m.front().t);
    m.resize(2001);  // 10 s
    const NavState end = integrate({s0.T_map_body.linear(), s0.T_map_body.translation(), s0.vel}, m,
                                   cfg.imu.gravity);
    const auto gt_end = interpolateAt(gt, m.back().t);
    ASSERT_TRUE(gt_end.has_value());
    SE3d T_map_imu = SE3d::Identity();
    T_map_imu.linear() = end.R;
    T_map_imu.translation() = end.p;
    const SE3d T_map_lidar = T_map_imu * T_imu_lidar;
    EXPECT_LT((T_map_lidar.translation() - gt_end->translation()).norm(), 0.05);
    EXPECT_TRUE(T_imu_lidar.isApprox(cfg.lidar.T_imu_lidar(), 1e-6));
}

TEST(Imu, WhiteNoiseHasTheConfiguredDensity) {
    ImuParams p;
    p.acc_bias_rw = p.gyro_bias_rw = p.acc_bias_init = p.gyro_bias_init = 0;
    ImuSimulator sim(p, 7);
    BodyState s;  // at rest, level
    double sa = 0, sg = 0;
    const int n = 20000;
    for (int k = 0; k < n; ++k) {
        const ImuSample m = sim.sample(s);
        sa += (m.acc - Vec3d(0, 0, p.gravity)).squaredNorm();
        sg += m.gyro.squaredNorm();
    }
    const double sigma_a = std::sqrt(sa / (3 * n)), sigma_g = std::sqrt(sg / (3 * n));
    EXPECT_NEAR(sigma_a, p.acc_noise_density * std::sqrt(p.rate_hz), 0.03 * sigma_a);
    EXPECT_NEAR(sigma_g, p.gyro_noise_density * std::sqrt(p.rate_hz), 0.03 * sigma_g);
}
