// End to end with IMU: a 3 s simulated office sequence (superloc-sim, when built) localized with
// IMU preintegration and deskew; every frame checked against the simulator's ground truth.
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/io/tum.h>
#include <superloc/localization/localize_app.h>
#include <superloc_testing/testing.h>

#include <filesystem>

using namespace superloc;
using namespace superloc::localization;
namespace fs = std::filesystem;

TEST(LocalizeSim, OfficeWithImuTracksGroundTruth) {
    const std::string sim = std::string(SUPERLOC_BINARY_DIR) + "/bin/superloc-sim";
    if (!fs::exists(sim)) GTEST_SKIP() << sim << " not built";
    const std::string dir = superloc::testing::freshDir("e2e_sim_office");
    const std::string cmd = sim + " " + superloc::testing::sourcePath("ini/sim/office.ini") + " --out " + dir +
                            "/seq --set sim.duration=3 > " + dir + "/sim.log 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;

    LocalizeApp app;
    ASSERT_EQ(app.initialize(std::vector<std::string>{
                  superloc::testing::sourcePath("ini/localize.ini"), "--rawlog", dir + "/seq/sequence.rawlog",
                  "--map", dir + "/seq/prior_map.pcd", "--initial-pose-tum", dir + "/seq/gt_tum.txt", "--out",
                  dir + "/out", "--quiet"}),
              LocalizeApp::Action::Run);
    ASSERT_EQ(app.run(), 0);
    const RunSummary& s = app.summary();
    EXPECT_GE(s.frames, 25u);
    EXPECT_EQ(s.used_imu, s.frames - 1) << "every frame after the first predicted with the IMU";
    EXPECT_EQ(s.diverged, 0u);

    const Trajectory gt = io::loadTum(dir + "/seq/gt_tum.txt");
    const Trajectory est = io::loadTum(dir + "/out/trajectory.tum");
    ASSERT_EQ(est.size(), s.frames);
    double se = 0, worst = 0;
    for (const auto& e : est) {
        const auto g = interpolateAt(gt, e.t, 1.0, 1e-3);
        ASSERT_TRUE(g.has_value()) << e.t;
        const double d = translationDistance(*g, e.pose);
        se += d * d;
        worst = std::max(worst, d);
        EXPECT_LT(rotationAngle(*g, e.pose) * 180 / M_PI, 1.0) << e.t;
    }
    const double ate = std::sqrt(se / static_cast<double>(est.size()));
    EXPECT_LT(ate, 0.03) << "ATE RMSE [m]";
    EXPECT_LT(worst, 0.10) << "worst frame [m]";
    std::cout << "sim office 3 s with IMU: ATE " << ate << " m, worst " << worst << " m\n";
}
