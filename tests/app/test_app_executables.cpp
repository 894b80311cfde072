// The superloc-eval and superloc-bench executables: exit codes and one-line errors (doc/design.md#9-command-line).
#include <gtest/gtest.h>
#include <superloc/app/process.h>
#include <superloc_testing/testing.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace superloc::app;

namespace {
struct AppRun {
    int code;
    std::string output;
};
AppRun run(const std::string& app, const std::vector<std::string>& args, const std::string& name) {
    const std::string log = superloc::testing::freshDir("exe_" + name) + "/out.log";
    std::vector<std::string> argv = {superloc::testing::appPath(app)};
    argv.insert(argv.end(), args.begin(), args.end());
    const ProcessResult p = runProcess(argv, log, 120);
    std::ifstream in(log);
    std::stringstream s;
    s << in.rdbuf();
    return {p.exit_code, s.str()};
}
size_t lines(const std::string& s) {
    size_t n = 0;
    for (char c : s) n += c == '\n';
    return n;
}
#define REQUIRE_APP(app)                                           \
    if (!std::filesystem::exists(superloc::testing::appPath(app))) \
    GTEST_SKIP() << app << " not built at " << superloc::testing::appPath(app)
}  // namespace

TEST(EvalExecutable, ExitCodesAndOneLineErrors) {
    REQUIRE_APP("superloc-eval");
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    const std::string gt = superloc::testing::sharedData("kitti00-mini/gt_velodyne_tum.txt");
    const AppRun ok = run("superloc-eval", {"--est", gt, "--gt", gt}, "eval_ok");
    EXPECT_EQ(ok.code, 0) << ok.output;
    EXPECT_NE(ok.output.find("| Rp / Rr | 1.0000 / 1.0000 |"), std::string::npos) << ok.output;
    EXPECT_EQ(run("superloc-eval", {"--help"}, "eval_help").code, 0);
    for (const auto& [args, expect] : std::vector<std::pair<std::vector<std::string>, std::string>>{
             {{"--est", "/nonexistent.tum", "--gt", gt}, "/nonexistent.tum: cannot open"},
             {{"--gt", gt}, "--est TUM is required"},
             {{"--est", gt, "--gt", gt, "--bogus"}, "not expected: --bogus (see --help)"},
             {{"--est", gt, "--gt", gt, "--set", "eval.map_voxel=abc"},
              "map_voxel = 'abc' is not a number"},
             {{"--est", gt, "--gt", gt, "--est-map", "/nonexistent.pcd", "--gt-map",
               "/nonexistent.ply"},
              "/nonexistent"}}) {
        const AppRun bad = run("superloc-eval", args, "eval_bad");
        EXPECT_EQ(bad.code, 1) << bad.output;
        EXPECT_EQ(lines(bad.output), 1u) << bad.output;
        EXPECT_EQ(bad.output.rfind("superloc-eval: ", 0), 0u) << bad.output;
        EXPECT_NE(bad.output.find(expect), std::string::npos) << bad.output;
    }
}

TEST(BenchExecutable, BadSuitesAreOneLineErrors) {
    REQUIRE_APP("superloc-bench");
    const std::string d = superloc::testing::freshDir("exe_bench_suite");
    std::ofstream(d + "/s.ini")
        << "[suite]\nmethods = icp\nsequences = a\nlocalize_config = nothere.ini\n";
    for (const auto& [args, expect] : std::vector<std::pair<std::vector<std::string>, std::string>>{
             {{d + "/s.ini", "--out", d + "/out"}, "nothere.ini does not exist"},
             {{d + "/missing.ini", "--out", d + "/out"}, "cannot open suite file"},
             {{d + "/s.ini"}, "--out is required"}}) {
        const AppRun bad = run("superloc-bench", args, "bench_bad");
        EXPECT_EQ(bad.code, 1) << bad.output;
        EXPECT_EQ(lines(bad.output), 1u) << bad.output;
        EXPECT_NE(bad.output.find(expect), std::string::npos) << bad.output;
    }
    EXPECT_EQ(run("superloc-bench", {"--help"}, "bench_help").code, 0);
}
