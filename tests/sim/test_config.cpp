// Configuration: presets merge under the file's own keys; bad input is a one-line ConfigError
// naming the file and key; the command line parses as documented.
#include <superloc/core/config.h>
#include <superloc/sim/worlds.h>

#include "sim_test_utils.h"

using namespace superloc;
using namespace superloc::sim;
using namespace superloc::app;

TEST(SimConfig, EveryCommittedWorldLoadsWithItsPreset) {
    for (const auto& w : worldNames()) {
        SCOPED_TRACE(w);
        const SimConfig c =
            loadSimConfig(superloc::testing::sourcePath("ini/sim/" + w + ".ini"), {});
        EXPECT_EQ(c.sim.world, w);
        if (w == "multifloor") {  // the legged robot's VLP-16
            EXPECT_EQ(c.lidar.beams, 16);
            EXPECT_EQ(c.lidar.columns, 1800);
        } else {  // OS1-64-like
            EXPECT_EQ(c.lidar.beams, 64);
            EXPECT_EQ(c.lidar.columns, 1024);
        }
        EXPECT_GE(c.sim.duration, 60.0);
    }
}

TEST(SimConfig, FileKeysOverridePresetAndSetOverridesFile) {
    const SimConfig c = simtest::worldConfig(
        "corridor", {"lidar.preset=../sensors/vlp16.ini", "lidar.ext_z=0.4"}, false);
    EXPECT_EQ(c.lidar.model, "vlp16");
    EXPECT_EQ(c.lidar.beams, 16);
    EXPECT_DOUBLE_EQ(c.lidar.ext_z, 0.4);
    const SimConfig d = simtest::worldConfig("corridor", {}, false);
    EXPECT_DOUBLE_EQ(d.lidar.ext_z, 0.15);  // from corridor.ini, over the preset's default
}

TEST(SimConfig, BadInputIsOneLineNamingFileAndKey) {
    const auto expectError = [](const std::vector<std::string>& sets, const std::string& part) {
        try {
            simtest::worldConfig("office", sets, false);
            ADD_FAILURE() << "no error for " << part;
        } catch (const ConfigError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("office.ini"), std::string::npos) << msg;
            EXPECT_NE(msg.find(part), std::string::npos) << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
    };
    expectError({"sim.wrold=office"}, "wrold");
    expectError({"lidar.beams=many"}, "beams");
    expectError({"lidar.beams=0"}, "beams");
    expectError({"imu.rate_hz=-1"}, "rate_hz");
    expectError({"sim.world=moon"}, "moon");
    expectError({"office.rooms_per_side=0"}, "rooms_per_side");
    expectError({"cave.roughness=9"}, "roughness");  // an unused world section is checked too
    expectError({"lidar.preset=nowhere.ini"}, "nowhere.ini");
    expectError({"odom_alt.drift_per_m=-0.1"}, "drift");
}

TEST(SimApp, CommandLine) {
    SimApp app;
    const char* help[] = {"superloc-sim", "--help"};
    EXPECT_FALSE(app.initialize(2, help));
    const std::string ini = superloc::testing::sourcePath("ini/sim/office.ini");
    const char* ok[] = {"superloc-sim", ini.c_str(), "--out", "/tmp/x",
                        "--seed",       "42",        "--set", "sim.duration=3"};
    EXPECT_TRUE(app.initialize(8, ok));
    EXPECT_EQ(app.config().sim.seed, 42u);
    EXPECT_DOUBLE_EQ(app.config().sim.duration, 3.0);
    EXPECT_EQ(app.outDir(), "/tmp/x");
    const char* bad_seed[] = {"superloc-sim", ini.c_str(), "--seed", "-1"};
    EXPECT_THROW(app.initialize(4, bad_seed), std::runtime_error);
    const char* no_ini[] = {"superloc-sim", "--out", "d"};
    EXPECT_THROW(app.initialize(3, no_ini), std::runtime_error);
    const char* unknown[] = {"superloc-sim", ini.c_str(), "--fast"};
    EXPECT_THROW(app.initialize(3, unknown), std::runtime_error);
    const char* missing_value[] = {"superloc-sim", ini.c_str(), "--out"};
    EXPECT_THROW(app.initialize(3, missing_value), std::runtime_error);
}
