// The trajectory's analytic derivatives match finite differences; platforms respect limits.
#include <superloc/core/se3.h>
#include <superloc/sim/imu_model.h>

#include "sim_test_utils.h"

using namespace superloc;
using namespace superloc::sim;

namespace {

void checkDerivatives(const SmoothTrajectory& tr) {
    const double h = 1e-3;  // times are ~1.7e9 s: resolution 2.4e-7 s
    for (double t = tr.startTime() + 0.5; t < tr.endTime() - 0.5; t += 0.73) {
        const BodyState s = tr.at(t), a = tr.at(t - h), b = tr.at(t + h);
        const Vec3d v_fd = (b.T_map_body.translation() - a.T_map_body.translation()) / (2 * h);
        const Vec3d a_fd = (b.vel - a.vel) / (2 * h);
        EXPECT_LT((v_fd - s.vel).norm(), 1e-3 * (1 + s.vel.norm())) << "t=" << t;
        EXPECT_LT((a_fd - s.acc).norm(), 1e-2 * (1 + s.acc.norm())) << "t=" << t;
        const Vec3d w_fd =
            logSO3(a.T_map_body.linear().transpose() * b.T_map_body.linear()) / (2 * h);
        EXPECT_LT((w_fd - s.omega_body).norm(), 1e-3 * (1 + s.omega_body.norm())) << "t=" << t;
    }
}

}  // namespace

TEST(Trajectory, DerivativesMatchFiniteDifferencesInEveryWorld) {
    for (const std::string w : {"corridor", "cave", "multifloor", "openfield", "office"}) {
        SCOPED_TRACE(w);
        const SimScene scene = makeScene(simtest::worldConfig(w, {"sim.duration=30"}));
        checkDerivatives(scene.trajectory);
    }
}

TEST(Trajectory, StartsAtRestAndKeepsTheCarLimits) {
    const SimConfig cfg = simtest::worldConfig("corridor");
    const SimScene scene = makeScene(cfg);
    const SmoothTrajectory& tr = scene.trajectory;
    const BodyState s0 = tr.at(tr.startTime());
    EXPECT_LT(s0.vel.norm(), 1e-9);
    EXPECT_LT(s0.acc.norm(), 1e-9);
    double vmax = 0, wmax = 0;
    for (double t = tr.startTime(); t <= tr.endTime(); t += 0.01) {
        const BodyState s = tr.at(t);
        vmax = std::max(vmax, s.vel.norm());
        wmax = std::max(wmax, std::abs(s.omega_body.z()));
    }
    // Up to 5 m/s and ~57 deg/s (the paper's RC car), and it really gets there.
    EXPECT_LE(vmax, cfg.trajectory.max_speed * 1.03);
    EXPECT_GE(vmax, cfg.trajectory.max_speed * 0.9);
    EXPECT_LE(wmax * 180 / M_PI, cfg.trajectory.max_yaw_rate_deg * 1.15);
    EXPECT_GE(wmax * 180 / M_PI, cfg.trajectory.max_yaw_rate_deg * 0.75);
    EXPECT_GE(tr.endTime() - tr.startTime(), 60.0);
}

TEST(Trajectory, CorridorIsLongAndNarrow) {
    const SimConfig cfg = simtest::worldConfig("corridor");
    const SimScene scene = makeScene(cfg);
    // The car spends a long stretch inside the 2-3 m corridor, at least 80 m from its closed end.
    double x_max_in_corridor = 0;
    for (double t = scene.trajectory.startTime(); t < scene.trajectory.endTime(); t += 0.05) {
        const Vec3d p = scene.trajectory.pose(t).translation();
        if (p.x() < cfg.ini.read_double("corridor", "length", 0)) {
            EXPECT_LT(std::abs(p.y()), 1.0) << "t=" << t;
            x_max_in_corridor = std::max(x_max_in_corridor, p.x());
        }
    }
    EXPECT_GE(x_max_in_corridor, 80.0);
}

TEST(Trajectory, MultifloorClimbsTwoStoreys) {
    const SimScene scene = makeScene(simtest::worldConfig("multifloor"));
    const auto& tr = scene.trajectory;
    const double z0 = tr.pose(tr.startTime()).translation().z(),
                 z1 = tr.pose(tr.endTime()).translation().z();
    EXPECT_NEAR(z1 - z0, 6.0, 0.1);
}
