// superloc-bench split for another scheduler (doc/evaluation.md#runs-split-for-a-scheduler):
// --plan prints a command per run, GNU parallel (or anything else) runs them, --collect writes
// the results. The superloc-bench executable with the stand-in tools of bench_stand_ins.h.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <superloc/app/bench_plan.h>
#include <superloc/app/process.h>
#include <superloc/app/suite.h>
#include <superloc_testing/bench_results.h>
#include <superloc_testing/testing.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench_stand_ins.h"

using namespace superloc::app;
using namespace superloc::testing::bench;
using superloc::testing::resultsJsonWithoutTimes;
using superloc::testing::resultsMarkdownWithoutTimes;
using superloc::testing::slurp;
namespace fs = std::filesystem;

namespace {

struct Shell {
    int code;
    std::string out;  ///< stdout and stderr
};

Shell sh(const std::string& command, const std::string& log) {
    fs::remove(log);
    const ProcessResult p = runProcess({"/bin/sh", "-c", command}, log, 300);
    return {p.exit_code, slurp(log)};
}

std::vector<std::string> lines(const std::string& s) {
    std::vector<std::string> out;
    std::istringstream in(s);
    for (std::string l; std::getline(in, l);)
        if (!l.empty()) out.push_back(l);
    return out;
}

/// superloc-bench on the suite of `d` with its stand-in tools, writing into `out`.
std::string bench(const std::string& d, const std::string& out) {
    const std::string exe = superloc::testing::appPath("superloc-bench");
    EXPECT_TRUE(fs::exists(exe)) << exe << " not built";
    return joinCommand({exe, d + "/suite.ini", "--out", out, "--tools", d + "/tools"});
}

#define REQUIRE_GNU_PARALLEL()                                                                  \
    if (findTool("parallel", "/nonexistent").empty())                                           \
    GTEST_SKIP() << "GNU parallel is not installed (apt-get install parallel, as "              \
                    "scripts/install-deps.sh does; CI has it)"

}  // namespace

TEST(BenchPlan, RunIdsIndicesAndShellWords) {
    SuiteSpec s;
    s.methods = {"superloc", "icp"};
    s.sequences.resize(2);
    s.sequences[0].name = "office", s.sequences[1].name = "kitti";
    const auto plan = planRuns(s);
    std::vector<std::string> ids;
    for (const auto& r : plan) ids.push_back(r.id);
    EXPECT_EQ(ids, (std::vector<std::string>{"data:office", "data:kitti", "office/superloc", "office/icp",
                                             "kitti/superloc", "kitti/icp"}));
    EXPECT_EQ(findRun(plan, "kitti/icp").index, 5u);
    EXPECT_EQ(findRun(plan, "4").id, "kitti/superloc");
    EXPECT_EQ(findRun(plan, "data:kitti").sequence, 1u);
    EXPECT_FALSE(findRun(plan, "data:kitti").method.has_value());
    EXPECT_EQ(*findRun(plan, "office/icp").method, 1u);
    for (const char* bad : {"6", "-1", "office/ndt", "data:", "", "2.0"}) {
        const std::string e = superloc::testing::errorOf([&] { findRun(plan, bad); });
        EXPECT_NE(e.find("--run: '" + std::string(bad) + "' is not a run of this plan"), std::string::npos) << e;
        EXPECT_NE(e.find("0-5"), std::string::npos) << e;
    }
    // Shell words: plain when safe, else single-quoted, and the shell gives them back as they were.
    EXPECT_EQ(shellQuote("/a/b-c_d.ini"), "/a/b-c_d.ini");
    EXPECT_EQ(shellQuote("data:office"), "data:office");
    EXPECT_EQ(shellQuote("a b"), "'a b'");
    EXPECT_EQ(shellQuote("it's"), "'it'\\''s'");
    EXPECT_EQ(shellQuote(""), "''");
    const std::string d = superloc::testing::freshDir("bench_plan_words");
    const std::vector<std::string> words = {"a b", "it's", "$HOME", "x;y", "*", "tab\there", "new\nline", ""};
    std::vector<std::string> argv = {"printf", "[%s]"};
    argv.insert(argv.end(), words.begin(), words.end());
    std::string expect;
    for (const auto& w : words) expect += "[" + w + "]";
    EXPECT_EQ(sh(joinCommand(argv), d + "/out.txt").out, expect);
    // The stamp of a run's configuration: changes with the suite, the localize INI or an override.
    const std::string a = configStamp("suite", "ini", {}), b = configStamp("suite", "ini", {"x.y=1"});
    EXPECT_EQ(a.size(), 16u);
    EXPECT_NE(a, b);
    EXPECT_NE(a, configStamp("suite ", "ini", {}));
    EXPECT_NE(configStamp("ab", "c", {}), configStamp("a", "bc", {}));
    EXPECT_EQ(a, configStamp("suite", "ini", {}));
}

// The acceptance test with stand-ins: `--plan | parallel -j 2`, then `--collect`, gives
// the tables, JSON and plots of `--jobs 1` except the measured and per-start fields
// (bench_results.h: the preamble, wall time, peak memory, "jobs").
TEST(BenchPlan, ParallelThenCollectGiveTheResultsOfOneJob) {
    REQUIRE_GNU_PARALLEL();
    const std::string d = superloc::testing::freshDir("bench_plan_parallel");
    writeTwoSequenceSuite(d, "good lift stop", 60);
    const Shell one = sh(bench(d, d + "/one") + " --jobs 1", d + "/one.log");
    EXPECT_EQ(one.code, 0) << one.out;

    // A blank in the output folder: the plan's commands must quote it.
    const std::string split = d + "/split out";
    const Shell run = sh(bench(d, split) + " --plan 2> " + shellQuote(d + "/plan.err") + " | tee " +
                             shellQuote(d + "/plan.txt") + " | parallel -j 2",
                         d + "/parallel.log");
    // The two `stop` runs exit 3: their --run exits 2, and parallel counts 2 failed jobs.
    EXPECT_EQ(run.code, 2) << run.out;
    const auto plan = lines(slurp(d + "/plan.txt"));
    ASSERT_EQ(plan.size(), 8u);
    const std::string exe = superloc::testing::appPath("superloc-bench");
    for (size_t i = 0; i < plan.size(); ++i) {
        EXPECT_EQ(plan[i].rfind(exe + " " + d + "/suite.ini --out '" + split + "' --tools ", 0), 0u) << plan[i];
        EXPECT_EQ(plan[i].find(" && ") != std::string::npos, i >= 2) << plan[i];
    }
    EXPECT_NE(plan[0].find("--run data:plane  # 0 data:plane"), std::string::npos) << plan[0];
    EXPECT_NE(plan[7].find("--run data:hall && "), std::string::npos) << plan[7];
    EXPECT_NE(plan[7].find("--run hall/stop  # 7 hall/stop (after data:hall = 1)"), std::string::npos) << plan[7];
    const std::string notes = slurp(d + "/plan.err");
    EXPECT_NE(notes.find("data runs 0-1 (data:SEQ), localization runs 2-7"), std::string::npos) << notes;
    EXPECT_NE(notes.find("--array=0-1 then --array=2-7"), std::string::npos) << notes;

    const Shell collect = sh(bench(d, split) + " --collect", d + "/collect.log");
    EXPECT_EQ(collect.code, 0) << collect.out;  // as --jobs 1: every run left a trajectory
    EXPECT_NE(collect.out.find("collected 6 of 6 runs"), std::string::npos) << collect.out;
    EXPECT_NE(collect.out.find("failed: plane/stop hall/stop"), std::string::npos) << collect.out;

    const std::string md1 = slurp(d + "/one/results.md"), md2 = slurp(split + "/results.md");
    EXPECT_EQ(resultsMarkdownWithoutTimes(md2), resultsMarkdownWithoutTimes(md1));
    EXPECT_NE(resultsMarkdownWithoutTimes(md2).find("| hall | stop | exit 3 | 6/11 |"), std::string::npos) << md2;
    EXPECT_NE(md2.find("Collected (--collect) from runs made one by one (--run); hosts "), std::string::npos) << md2;
    const std::string js1 = slurp(d + "/one/results.json"), js2 = slurp(split + "/results.json");
    EXPECT_EQ(resultsJsonWithoutTimes(js2), resultsJsonWithoutTimes(js1));
    EXPECT_TRUE(nlohmann::json::parse(js2)["jobs"].is_null());  // not known: parallel decided
    for (const char* f : {"plane_good_top.svg", "plane_good_gamma.svg", "hall_lift_top.svg", "hall_f1_rot.svg",
                          "plane_f1_trans.svg"})
        EXPECT_EQ(slurp(split + "/" + f), slurp(d + "/one/" + f)) << f;

    // --collect needs of the data only the ground truth: a collecting machine may copy runs/ and
    // data/SEQ/{gt_tum.txt, gt_map.ply, complete} without the rawlogs and prior maps.
    for (const char* seq : {"plane", "hall"})
        fs::remove(split + "/data/" + seq + "/sequence.rawlog"), fs::remove(split + "/data/" + seq + "/prior_map.pcd");
    EXPECT_EQ(sh(bench(d, split) + " --collect", d + "/collect.log").code, 0);
    EXPECT_EQ(resultsMarkdownWithoutTimes(slurp(split + "/results.md")), resultsMarkdownWithoutTimes(md1));

    // Each run's status file: what --collect read.
    const auto st = nlohmann::json::parse(slurp(split + "/runs/hall/stop/status.json"));
    EXPECT_EQ(st["id"], "hall/stop");
    EXPECT_EQ(st["status"], "exit 3");
    EXPECT_EQ(st["exit_code"], 3);
    EXPECT_FALSE(st["version"].get<std::string>().empty());
    EXPECT_FALSE(st["host"].get<std::string>().empty());
    EXPECT_EQ(st["config"].get<std::string>().size(), 16u);
    EXPECT_TRUE(fs::exists(split + "/data/hall/complete"));
}

TEST(BenchPlan, CollectNamesMissingAndFailedRuns) {
    const std::string d = superloc::testing::freshDir("bench_plan_missing");
    writeTwoSequenceSuite(d, "good stop lift", 60);
    const std::string b = bench(d, d + "/out");
    const auto run = [&](const std::string& id) { return sh(b + " --run " + id, d + "/run.log"); };
    ASSERT_EQ(sh(b + " --plan", d + "/plan.log").code, 0);
    EXPECT_EQ(run("data:plane").code, 0);
    EXPECT_EQ(run("plane/good").code, 0);
    const Shell stop = run("plane/stop");
    EXPECT_EQ(stop.code, 2) << stop.out;  // the child failed: its status file says so
    EXPECT_NE(stop.out.find("plane/stop: exit 3"), std::string::npos) << stop.out;
    // plane/lift never runs: missing.
    // A localization run before its data: a one-line error naming the data run to do first.
    const Shell early = run("hall/good");
    EXPECT_EQ(early.code, 1) << early.out;
    ASSERT_FALSE(lines(early.out).empty());
    EXPECT_EQ(lines(early.out).back(),
              "superloc-bench: --run hall/good: its data is not ready (data:hall has not finished (no " + d +
                  "/out/data/hall/complete)): run data:hall (1) first");
    // A data run that fails (the simulator exits 5): its runs have no data, and say why.
    writeScript(d + "/tools/superloc-sim", "exit 5\n");
    const Shell data = run("1");
    EXPECT_EQ(data.code, 2) << data.out;
    EXPECT_NE(data.out.find("  data:hall: sim exit 5 (see logs/hall-sim.log)"), std::string::npos) << data.out;
    const Shell after = run("hall/good");
    EXPECT_EQ(after.code, 1) << after.out;
    EXPECT_NE(after.out.find("--run hall/good: its data is not ready (sim exit 5"), std::string::npos) << after.out;

    const Shell collect = sh(b + " --collect", d + "/collect.log");
    EXPECT_EQ(collect.code, 2) << collect.out;
    for (const char* named :
         {"  plane / lift: missing: no runs/plane/lift/status.json (not run, still running, or killed)",
          "  plane / stop: exit 3, ATE", "  hall / good: no data: sim exit 5",
          "collected 5 of 6 runs", "failed: plane/stop hall/good hall/stop hall/lift", "missing: plane/lift (--run each"})
        EXPECT_NE(collect.out.find(named), std::string::npos) << named << "\n" << collect.out;
    const std::string md = slurp(d + "/out/results.md");
    EXPECT_NE(md.find("- plane / lift: missing: no runs/plane/lift/status.json"), std::string::npos) << md;
    EXPECT_NE(md.find("- plane / stop: exit 3"), std::string::npos) << md;
    const auto js = nlohmann::json::parse(slurp(d + "/out/results.json"));
    ASSERT_EQ(js["runs"].size(), 6u);
    EXPECT_EQ(js["runs"][2]["method"], "lift");
    EXPECT_EQ(js["runs"][2]["status"].get<std::string>().rfind("missing", 0), 0u);

    // The missing run, run late, completes the collection (hall's data still failed).
    EXPECT_EQ(run("plane/lift").code, 0);
    const Shell again = sh(b + " --collect", d + "/collect.log");
    EXPECT_EQ(again.code, 2) << again.out;
    EXPECT_EQ(again.out.find("missing:"), std::string::npos) << again.out;

    // An edited suite is another configuration: --run refuses the old plan, and after --plan the
    // runs made before are stale.
    std::ofstream(d + "/suite.ini", std::ios::app) << "; edited\n";
    const Shell old_plan = run("plane/good");
    EXPECT_EQ(old_plan.code, 1);
    EXPECT_NE(old_plan.out.find("--run: " + d + "/out/plan.json was planned with another suite"), std::string::npos)
        << old_plan.out;
    ASSERT_EQ(sh(b + " --plan", d + "/plan.log").code, 0);
    const Shell stale = sh(b + " --collect", d + "/collect.log");
    EXPECT_EQ(stale.code, 2);
    EXPECT_NE(stale.out.find("plane / good: stale: runs/plane/good ran with another suite"), std::string::npos)
        << stale.out;
}

TEST(BenchPlan, DataRunsPrepareOnceAndCheckTheirFiles) {
    const std::string d = superloc::testing::freshDir("bench_plan_data");
    const std::string tools = writeTwoSequenceSuite(d, "good", 60);
    // A slow simulator that counts its runs.
    writeScript(tools + "/superloc-sim",
                std::string(kParse) + "echo run >> \"$(dirname \"$0\")/sim.count\"; sleep 2\n" + kSim);
    const std::string b = bench(d, d + "/out");
    ASSERT_EQ(sh(b + " --plan", d + "/plan.log").code, 0);
    // Two preparations of one sequence at once (as two plan lines of its runs would start): one
    // simulates, the other waits for it and finds the data complete.
    const Shell both = sh(b + " --run data:plane > " + shellQuote(d + "/a.log") + " 2>&1 & " + b +
                              " --run data:plane > " + shellQuote(d + "/b.log") + " 2>&1 & wait",
                          d + "/both.log");
    const std::string a_log = slurp(d + "/a.log"), b_log = slurp(d + "/b.log");
    EXPECT_EQ(lines(slurp(tools + "/sim.count")).size(), 1u) << a_log << b_log;
    const std::string logs = a_log + b_log;
    EXPECT_NE(logs.find("plane: waited for another run preparing its data"), std::string::npos) << logs;
    EXPECT_NE(logs.find("plane: data complete, reused"), std::string::npos) << logs;
    EXPECT_EQ(lines(logs).back(), "  data:plane: ok") << logs;
    const auto st = nlohmann::json::parse(slurp(d + "/out/data/plane/status.json"));
    EXPECT_EQ(st["status"], "ok");
    EXPECT_EQ(st["exit_code"], 0);
    // A file changed after the marker was written (a truncated copy): the data is not complete
    // any more; the localization run refuses it and the data run prepares it again.
    std::ofstream(d + "/out/data/plane/sequence.rawlog", std::ios::app) << "more";
    const Shell loc = sh(b + " --run plane/good", d + "/loc.log");
    EXPECT_EQ(loc.code, 1);
    EXPECT_NE(loc.out.find("sequence.rawlog has 8 bytes, not the 4 it had when written"), std::string::npos)
        << loc.out;
    EXPECT_EQ(sh(b + " --run data:plane", d + "/again.log").code, 0);
    EXPECT_EQ(lines(slurp(tools + "/sim.count")).size(), 2u);
    EXPECT_EQ(sh(b + " --run plane/good", d + "/loc.log").code, 0);
}
