// superloc-bench split for another scheduler, on the quick suite without its corridor
// (ini/bench/quick.ini --sequences "office kitti00-mini", superloc and icp: the suite runs twice
// here, and BenchQuick.Smoke runs all of it; doc/evaluation.md#runs-split-for-a-scheduler):
// `--plan | parallel -j 2`, then `--collect`, gives the tables, JSON and plots of `--jobs 1`.
// Left out of the comparison (superloc_testing/bench_results.h), because they are measured or
// say how the runs were started: results.md's preamble (command, date, the --collect note), the
// "ms per frame" table and the Runs table's wall time and peak memory; results.json's "jobs"
// (null after --collect) and each run's wall_s, peak_rss_mb and metrics.timing / metrics.stages.
// Everything else (ATE, Rp, Rr, map outliers, frame counts, health, consistency, risk, the
// statuses, plots) must be equal: the apps are deterministic for one input.
#include <gtest/gtest.h>
#include <superloc/app/process.h>
#include <superloc/app/suite.h>
#include <superloc_testing/bench_results.h>
#include <superloc_testing/testing.h>

#include <filesystem>

namespace fs = std::filesystem;
using namespace superloc::app;

using superloc::testing::slurp;

TEST(BenchQuick, PlanThroughParallelGivesTheResultsOfOneJob) {
    if (findTool("parallel", "/nonexistent").empty())
        GTEST_SKIP() << "GNU parallel is not installed (apt-get install parallel, as "
                        "scripts/install-deps.sh does; CI has it)";
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const std::string exe = superloc::testing::appPath("superloc-bench");
    ASSERT_TRUE(fs::exists(exe)) << exe << " not built";
    const std::string d = superloc::testing::freshDir("bench_quick_plan");
    const std::string bench = joinCommand({exe, superloc::testing::sourcePath("ini/bench/quick.ini"), "--sequences",
                                           "office kitti00-mini", "--out"});
    const auto sh = [&](const std::string& command, const std::string& log) {
        const ProcessResult p = runProcess({"/bin/sh", "-c", command}, d + "/" + log, 900);
        return std::make_pair(p.exit_code, slurp(d + "/" + log));
    };
    const auto one = sh(bench + " " + shellQuote(d + "/one") + " --jobs 1", "one.log");
    ASSERT_EQ(one.first, 0) << one.second;
    const auto split = sh(bench + " " + shellQuote(d + "/split") + " --plan | parallel -j 2", "parallel.log");
    ASSERT_EQ(split.first, 0) << split.second;
    const auto collect = sh(bench + " " + shellQuote(d + "/split") + " --collect", "collect.log");
    ASSERT_EQ(collect.first, 0) << collect.second;
    EXPECT_NE(collect.second.find("collected 4 of 4 runs"), std::string::npos) << collect.second;

    using superloc::testing::resultsJsonWithoutTimes;
    using superloc::testing::resultsMarkdownWithoutTimes;
    const std::string md1 = slurp(d + "/one/results.md"), md2 = slurp(d + "/split/results.md");
    EXPECT_EQ(resultsMarkdownWithoutTimes(md2, true), resultsMarkdownWithoutTimes(md1, true));
    EXPECT_NE(resultsMarkdownWithoutTimes(md1, true).find("| kitti00-mini | icp | ok |"), std::string::npos) << md1;
    EXPECT_EQ(resultsJsonWithoutTimes(slurp(d + "/split/results.json"), true),
              resultsJsonWithoutTimes(slurp(d + "/one/results.json"), true));
    size_t svgs = 0;
    for (const auto& e : fs::directory_iterator(d + "/one"))
        if (e.path().extension() == ".svg") {
            ++svgs;
            EXPECT_EQ(slurp(d + "/split/" + e.path().filename().string()), slurp(e.path().string()))
                << e.path().filename();
        }
    EXPECT_EQ(svgs, 2u * 2u * 2u + 2u * 2u);  // per run a top view and a γ timeline; per sequence two F1
}
