// superloc-bench's runner end to end with stand-in tools (shell scripts honouring the apps'
// command lines), so the suite logic is tested without the real simulator and localizer.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <superloc/app/bench_app.h>
#include <superloc/core/config.h>
#include <superloc/app/process.h>
#include <superloc_testing/testing.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace superloc;
using namespace superloc::eval;
using namespace superloc::app;
namespace fs = std::filesystem;

namespace {
void writeScript(const std::string& path, const std::string& body) {
    std::ofstream(path) << "#!/bin/sh\n" << body;
    ::chmod(path.c_str(), 0755);
}
std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// Argument parsing shared by the stand-ins: sets OUT, METHOD, GT from the flags.
const char* kParse =
    "while [ $# -gt 0 ]; do case \"$1\" in --out) OUT=$2; shift;; --method) METHOD=$2; shift;;"
    " --initial-pose-tum) GT=$2; shift;; esac; shift; done\n";

// superloc-sim: 11 GT poses 1 m apart along x; GT map = 21 x 3 points on the plane z = 0.
const char* kSim =
    "mkdir -p \"$OUT\"; echo raw > \"$OUT/sequence.rawlog\"; echo map > \"$OUT/prior_map.pcd\"\n"
    "i=0; : > \"$OUT/gt_tum.txt\"; while [ $i -le 10 ]; do echo \"$i.0 $i 0 0 0 0 0 1\" >> "
    "\"$OUT/gt_tum.txt\"; i=$((i+1)); done\n"
    "{ printf 'ply\\nformat ascii 1.0\\nelement vertex 63\\nproperty float x\\nproperty float "
    "y\\nproperty float z\\nend_header\\n';\n"
    "  for x in 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20; do for y in 0 1 2; do echo "
    "\"$x $y 0\"; done; done; } > \"$OUT/gt_map.ply\"\n";

// superloc-localize: `good` reproduces GT with its map on the plane; `lift` is 0.2 m too high;
// `stop` writes the first 6 poses and fails (exit 3).
const char* kLocalize =
    "mkdir -p \"$OUT\"; Z=0; N=11; RC=0\n"
    "[ \"$METHOD\" = lift ] && Z=0.2\n"
    "[ \"$METHOD\" = stop ] && N=6 && RC=3\n"
    "head -n $N \"$GT\" | awk -v z=$Z '{ $4 = $4 + z; print }' > \"$OUT/trajectory.tum\"\n"
    "echo 't,gamma_x,gamma_y,gamma_z,gamma_roll,gamma_pitch,gamma_yaw,degenerate,ms_total' > "
    "\"$OUT/frames.csv\"\n"
    "i=0; while [ $i -lt $N ]; do echo \"$i.0,0.1,1,1,1,1,1,x,$((10+i))\" >> \"$OUT/frames.csv\"; "
    "i=$((i+1)); done\n"
    "{ printf '# .PCD v0.7\\nVERSION 0.7\\nFIELDS x y z\\nSIZE 4 4 4\\nTYPE F F F\\nCOUNT 1 1 "
    "1\\nWIDTH 3\\nHEIGHT 1\\n"
    "VIEWPOINT 0 0 0 1 0 0 0\\nPOINTS 3\\nDATA ascii\\n'; echo \"1 1 $Z\"; echo \"5 1 $Z\"; echo "
    "\"9 2 $Z\"; } > \"$OUT/localized_map.pcd\"\n"
    "exit $RC\n";
}  // namespace

TEST(BenchApp, RunsASuiteWithStandInTools) {
    const std::string d = superloc::testing::freshDir("bench_app");
    const std::string tools = d + "/tools";
    fs::create_directories(tools);
    writeScript(tools + "/superloc-sim", std::string(kParse) + kSim);
    writeScript(tools + "/superloc-localize", std::string(kParse) + kLocalize);
    std::ofstream(d + "/localize.ini") << "[localization]\n";
    std::ofstream(d + "/world.ini") << "[sim]\n";
    std::ofstream(d + "/suite.ini") << "[suite]\nmethods = good lift stop\nsequences = "
                                       "plane\nlocalize_config = localize.ini\ntimeout = 60\n"
                                    << "[seq.plane]\ntype = sim\nconfig = world.ini\nseed = 3\n";
    BenchApp app;
    app.initialize({d + "/suite.ini", "--out", d + "/out", "--tools", tools});
    std::ostringstream log;
    EXPECT_EQ(app.run(log), 0) << log.str();
    ASSERT_EQ(app.runs.size(), 3u);

    const RunRecord& good = app.runs[0];
    EXPECT_EQ(good.status, "ok");
    ASSERT_TRUE(good.result && good.result->map);
    EXPECT_NEAR(good.result->ate.trans.rmse, 0, 1e-9);
    EXPECT_DOUBLE_EQ(good.result->map->outlier_percent, 0.0);
    EXPECT_NEAR(good.result->rp.area, 1 - std::exp(-10.0), 1e-9);
    EXPECT_DOUBLE_EQ(good.result->timing->median_ms, 15.0);  // 10..20 ms
    EXPECT_DOUBLE_EQ(*good.result->degenerate_frame_percent, 100.0);
    EXPECT_DOUBLE_EQ(good.gt_length_m, 10.0);

    const RunRecord& lift = app.runs[1];
    EXPECT_NEAR(lift.result->ate.trans.rmse, 0.2, 1e-9);  // 0.2 m too high everywhere
    EXPECT_DOUBLE_EQ(lift.result->map->outlier_percent, 100.0);

    const RunRecord& stop = app.runs[2];
    EXPECT_EQ(stop.status, "exit 3");
    ASSERT_TRUE(stop.result);
    // 5 of 10 GT steps, all exact: P = 1, R = 0.5, F1 = 2/3.
    EXPECT_NEAR(stop.result->rp.area, 2.0 / 3.0 * (1 - std::exp(-10.0)), 1e-9);

    const std::string md = slurp(d + "/out/results.md");
    EXPECT_NE(md.find("| Method | plane |"), std::string::npos) << md;
    EXPECT_NE(md.find("| good | **0.00** |"), std::string::npos) << md;
    EXPECT_NE(md.find("| stop | 0.00 † |"), std::string::npos) << md;
    const auto json = nlohmann::json::parse(slurp(d + "/out/results.json"));
    ASSERT_EQ(json["runs"].size(), app.runs.size());
    const auto& lift_json = json["runs"][1];
    EXPECT_EQ(lift_json["method"], "lift");
    EXPECT_NEAR(lift_json["metrics"]["ate"]["trans_m"]["rmse"].get<double>(), 0.2, 1e-9);
    EXPECT_NEAR(lift_json["metrics"]["map"]["outlier_percent"].get<double>(), 100.0, 1e-9);
    EXPECT_EQ(json["runs"][2]["status"], "exit 3");
    EXPECT_NE(md.find("![plane_good_top.svg](plane_good_top.svg)"), std::string::npos) << md;
    EXPECT_NE(md.find("![plane_f1_rot.svg](plane_f1_rot.svg)"), std::string::npos) << md;
    for (const char* f :
         {"plane_good_top.svg", "plane_good_gamma.svg", "plane_f1_trans.svg", "plane_f1_rot.svg"})
        EXPECT_TRUE(fs::exists(d + "/out/" + f)) << f;

    // A second run reuses the simulated data (no sim tool needed any more).
    fs::remove(tools + "/superloc-sim");
    BenchApp again;
    again.initialize({d + "/suite.ini", "--out", d + "/out", "--tools", tools, "--methods", "good",
                      "--localize-set", "localization.association=voxel"});
    std::ostringstream log2;
    EXPECT_EQ(again.run(log2), 0) << log2.str();
    EXPECT_EQ(again.runs.size(), 1u);
    // --localize-set reaches the localize run, and results.md's command line records it.
    EXPECT_NE(log2.str().find("--set localization.association=voxel"), std::string::npos) << log2.str();
    EXPECT_NE(slurp(d + "/out/results.md").find("--localize-set localization.association=voxel"),
              std::string::npos);
}

TEST(BenchApp, MissingToolsAndBadArgumentsAreReported) {
    const std::string d = superloc::testing::freshDir("bench_app_missing");
    std::ofstream(d + "/localize.ini") << "[localization]\n";
    std::ofstream(d + "/world.ini") << "[sim]\n";
    std::ofstream(d + "/suite.ini")
        << "[suite]\nmethods = icp\nsequences = w\nlocalize_config = localize.ini\n"
        << "[seq.w]\ntype = sim\nconfig = world.ini\n";
    BenchApp app;
    app.initialize({d + "/suite.ini", "--out", d + "/out", "--tools", d + "/none"});
    std::ostringstream log;
    if (!findTool("superloc-sim", d + "/none").empty()) GTEST_SKIP() << "superloc-sim is on PATH";
    EXPECT_EQ(app.run(log), 2);
    ASSERT_EQ(app.runs.size(), 1u);
    EXPECT_NE(app.runs[0].status.find("superloc-sim not found"), std::string::npos)
        << app.runs[0].status;
    EXPECT_THROW(BenchApp().initialize({d + "/suite.ini"}), ConfigError);  // no --out
    EXPECT_THROW(BenchApp().initialize({"--out", d}), ConfigError);        // no SUITE.ini
    EXPECT_THROW(BenchApp().initialize({d + "/suite.ini", "--out", d, "--sequences", "zzz"}),
                 std::invalid_argument);
    for (const char* bad : {"association=voxel", "localization.association", ".key=1", "section.=1"})
        EXPECT_THROW(BenchApp().initialize({d + "/suite.ini", "--out", d, "--localize-set", bad}),
                     std::invalid_argument)
            << bad;
}
