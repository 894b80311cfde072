// The same seed gives byte-identical outputs; another seed gives another sequence.
#include "sim_test_utils.h"

using namespace superloc;
using namespace superloc::sim;
using namespace superloc::app;

namespace {

void generate(const std::string& dir, uint64_t seed) {
    const SimConfig cfg = simtest::worldConfig(
        "cave",
        {"sim.duration=1.5", "sim.gt_map_spacing=0.05", "sim.seed=" + std::to_string(seed)});
    SimApp app;
    app.setMinLoggingLevel(mrpt::system::LVL_WARN);
    app.initialize(cfg, dir);
    app.run();
}

}  // namespace

TEST(Determinism, SameSeedByteIdenticalOutputs) {
    const std::string a = superloc::testing::freshDir("sim_det_a"),
                      b = superloc::testing::freshDir("sim_det_b"),
                      c = superloc::testing::freshDir("sim_det_c");
    generate(a, 5);
    generate(b, 5);
    generate(c, 6);
    for (const char* f : {"sequence.rawlog", "gt_tum.txt", "gt_map.ply", "prior_map.pcd",
                          "topview.svg", "config.ini"}) {
        SCOPED_TRACE(f);
        const std::string fa = simtest::readFile(a + "/" + f), fb = simtest::readFile(b + "/" + f);
        ASSERT_GT(fa.size(), 100u);
        EXPECT_TRUE(fa == fb);
    }
    // Another seed: another cave, other noise.
    EXPECT_FALSE(simtest::readFile(a + "/sequence.rawlog") ==
                 simtest::readFile(c + "/sequence.rawlog"));
    EXPECT_FALSE(simtest::readFile(a + "/gt_map.ply") == simtest::readFile(c + "/gt_map.ply"));
}
