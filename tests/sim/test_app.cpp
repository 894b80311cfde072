// The superloc-sim executable: --help, exit codes, one-line errors, the documented outputs.
// Skipped when the app has not been built (it is built with the `superloc-sim` target).
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>

#include "sim_test_utils.h"

namespace {

struct AppRun {
    int code = -1;
    std::string out;  // stdout + stderr
};

AppRun runApp(const std::string& args) {
    AppRun r;
    const std::string cmd = superloc::testing::appPath("superloc-sim") + " " + args + " 2>&1";
    FILE* f = popen(cmd.c_str(), "r");
    if (!f) return r;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) r.out.append(buf, n);
    const int status = pclose(f);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

#define REQUIRE_APP()                                                         \
    if (!std::filesystem::exists(superloc::testing::appPath("superloc-sim"))) \
    GTEST_SKIP() << "superloc-sim not built at " << superloc::testing::appPath("superloc-sim")

}  // namespace

TEST(SimAppExe, HelpAndErrors) {
    REQUIRE_APP();
    const AppRun help = runApp("--help");
    EXPECT_EQ(help.code, 0);
    EXPECT_NE(help.out.find("Usage: superloc-sim [OPTIONS] CONFIG.ini"), std::string::npos) << help.out;

    const std::string ini = superloc::testing::sourcePath("ini/sim/office.ini");
    const AppRun dump = runApp(ini + " --dump-config --set imu.rate_hz=400");
    EXPECT_EQ(dump.code, 0) << dump.out;
    for (const char* sect : {"[sim]", "[trajectory]", "[lidar]", "[imu]", "[odom_alt]", "[office]"})
        EXPECT_NE(dump.out.find(sect), std::string::npos) << sect;
    EXPECT_NE(dump.out.find("400.0"), std::string::npos) << dump.out;
    for (const std::string& bad :
         {std::string("/no/such.ini"), ini + " --set lidar.beamz=3", ini + " --seed x",
          ini + " --set office.door_width=9", std::string(""), ini + " --bogus"}) {
        const AppRun r = runApp(bad);
        EXPECT_EQ(r.code, 1) << bad << ": " << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << bad << ": " << r.out;
        EXPECT_EQ(r.out.rfind("superloc-sim: ", 0), 0u) << r.out;
    }
}

TEST(SimAppExe, WritesTheDocumentedOutputs) {
    REQUIRE_APP();
    const std::string dir = superloc::testing::freshDir("sim_app_exe");
    const AppRun r = runApp(
        superloc::testing::sourcePath("ini/sim/multifloor.ini") + " --out " + dir +
        " --seed 3 --set sim.duration=1 --set sim.gt_map_spacing=0.2 --set lidar.columns=64");
    ASSERT_EQ(r.code, 0) << r.out;
    for (const char* f : {"sequence.rawlog", "gt_tum.txt", "gt_map.ply", "prior_map.pcd",
                          "topview.svg", "config.ini"})
        EXPECT_GT(std::filesystem::file_size(dir + "/" + f), 100u) << f;
    // The effective configuration reproduces the run: same seed, no preset needed.
    const auto cfg = superloc::sim::loadSimConfig(dir + "/config.ini", {});
    EXPECT_EQ(cfg.sim.seed, 3u);
    EXPECT_EQ(cfg.lidar.columns, 64);
    EXPECT_EQ(cfg.lidar.beams, 16);
}
