// Every world's rawlog passes `rawlog-edit --info` (skipped when mrpt-apps is not installed),
// with the expected sensor labels and rates.
#include <cstdio>
#include <cstdlib>

#include "sim_test_utils.h"

using namespace superloc;
using namespace superloc::sim;
using namespace superloc::app;

namespace {

bool haveRawlogEdit() { return std::system("command -v rawlog-edit > /dev/null 2>&1") == 0; }

std::string runCapture(const std::string& cmd, int& rc) {
    std::string out;
    FILE* f = popen(cmd.c_str(), "r");
    if (!f) return rc = -1, out;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
    rc = pclose(f);
    return out;
}

}  // namespace

TEST(RawlogInfo, EveryWorldPassesRawlogEdit) {
    if (!haveRawlogEdit()) GTEST_SKIP() << "rawlog-edit not on PATH (apt install mrpt-apps)";
    for (const std::string w : {"corridor", "cave", "multifloor", "openfield", "office"}) {
        SCOPED_TRACE(w);
        const std::string dir = superloc::testing::freshDir("sim_rawlog_info_" + w);
        const SimConfig cfg = simtest::worldConfig(
            w, {"sim.duration=1", "sim.gt_map_spacing=0.3", "sim.prior_map_voxel=0.3",
                "lidar.beams=8", "lidar.columns=128"});
        SimApp app;
        app.setMinLoggingLevel(mrpt::system::LVL_WARN);
        app.initialize(cfg, dir);
        const SimSummary sum = app.run();
        EXPECT_EQ(sum.scans, 10u);
        EXPECT_EQ(sum.imu, 201u);
        int rc = 0;
        const std::string out =
            runCapture("rawlog-edit --info -i '" + dir + "/sequence.rawlog' 2>&1", rc);
        EXPECT_EQ(rc, 0) << out;
        for (const char* label : {"lidar", "imu", "odom_alt", "gt"})
            EXPECT_NE(out.find(std::string(label) + " /"), std::string::npos) << label << "\n"
                                                                              << out;
        EXPECT_NE(out.find("Observations format               : Yes"), std::string::npos) << out;
    }
}
