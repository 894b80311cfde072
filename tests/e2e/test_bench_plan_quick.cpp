// superloc-bench split for another scheduler, on a cut-down quick suite (ini/bench/quick.ini's
// office, 6 s instead of 12, and kitti00-mini, superloc and icp: the suite runs twice here, and
// BenchQuick.Smoke runs the whole quick suite; doc/evaluation.md#runs-split-for-a-scheduler):
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
#include <fstream>

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
    // quick.ini's office and kitti00-mini sections as they are, the office shorter.
    const std::string ini = d + "/suite.ini";
    std::ofstream(ini) << "[suite]\nmethods = superloc icp\nsequences = office kitti00-mini\n"
                       << "localize_config = " << superloc::testing::sourcePath("ini/localize.ini") << "\n"
                       << "localize_set = run.localized_map_voxel=0.05\ntimeout = 300\n"
                       << "[eval]\nassoc_tolerance = 0.02\noutlier_threshold = 0.10\nmap_voxel = 0.05\n"
                       << "[seq.office]\ntype = sim\nconfig = " << superloc::testing::sourcePath("ini/sim/office.ini")
                       << "\nseed = 1\nsim_set = sim.duration=6\n"
                       << "[seq.kitti00-mini]\ntype = kitti\ndata = kitti00-mini\ngt = gt_velodyne_tum.txt\n"
                       << "prior_voxel = 0.1\nmap_scans = even\nlocalize_scans = odd\n"
                       << "localize_set = features.deskew=false\n";
    const std::string bench = joinCommand({exe, ini, "--out"});
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
