// superloc-bench's runner end to end with stand-in tools (shell scripts honouring the apps'
// command lines), so the suite logic is tested without the real simulator and localizer.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <superloc/app/bench_app.h>
#include <superloc/core/config.h>
#include <superloc/app/process.h>
#include <superloc/app/task_queue.h>
#include <superloc_testing/bench_results.h>
#include <superloc_testing/testing.h>
#include <sys/stat.h>

#include "bench_stand_ins.h"

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace superloc;
using namespace superloc::eval;
using namespace superloc::app;
namespace fs = std::filesystem;

using namespace superloc::testing::bench;
using superloc::testing::resultsJsonWithoutTimes;
using superloc::testing::resultsMarkdownWithoutTimes;
using superloc::testing::slurp;

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
                      "--localize-set", "association.kind=voxel"});
    std::ostringstream log2;
    EXPECT_EQ(again.run(log2), 0) << log2.str();
    EXPECT_EQ(again.runs.size(), 1u);
    // --localize-set reaches the localize run, and results.md's command line records it.
    EXPECT_NE(log2.str().find("--set association.kind=voxel"), std::string::npos) << log2.str();
    EXPECT_NE(slurp(d + "/out/results.md").find("--localize-set association.kind=voxel"),
              std::string::npos);
}

/// A suite of simulated sequences (its [suite] and [seq.*] text `body`) with an empty localize
/// INI and an empty world INI beside it, in `d`.
static void writeSimSuite(const std::string& d, const std::string& body) {
    std::ofstream(d + "/localize.ini") << "[localization]\n";
    std::ofstream(d + "/world.ini") << "[sim]\n";
    std::ofstream(d + "/suite.ini") << body;
}

TEST(BenchApp, MissingToolsAndBadArgumentsAreReported) {
    const std::string d = superloc::testing::freshDir("bench_app_missing");
    writeSimSuite(d, "[suite]\nmethods = icp\nsequences = w\nlocalize_config = localize.ini\n"
                     "[seq.w]\ntype = sim\nconfig = world.ini\n");
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

// --sequences takes a seeded sequence's section name for all its seeds (what a user reads in the
// suite file), or NAME_sN for one seed; listing both keeps each sequence once.
TEST(BenchApp, SequencesBySectionNameTakeEverySeed) {
    const std::string d = superloc::testing::freshDir("bench_app_sequence_groups");
    writeSimSuite(d, "[suite]\nmethods = icp\nsequences = w v\nlocalize_config = localize.ini\n"
                     "[seq.w]\ntype = sim\nconfig = world.ini\nseeds = 1 2 3\n"
                     "[seq.v]\ntype = sim\nconfig = world.ini\n");
    BenchApp app;
    app.initialize({d + "/suite.ini", "--out", d + "/out", "--sequences", "v w w_s2"});
    std::vector<std::string> names;
    for (const auto& q : app.suite.sequences) names.push_back(q.name);
    EXPECT_EQ(names, (std::vector<std::string>{"v", "w_s1", "w_s2", "w_s3"}));
    BenchApp one;
    one.initialize({d + "/suite.ini", "--out", d + "/out", "--sequences", "w_s3"});
    ASSERT_EQ(one.suite.sequences.size(), 1u);
    EXPECT_EQ(one.suite.sequences[0].name, "w_s3");
    EXPECT_THROW(BenchApp().initialize({d + "/suite.ini", "--out", d, "--sequences", "w_s4"}),
                 std::invalid_argument);
}

TEST(BenchApp, JobsGiveTheResultsOfOneJob) {
    const std::string d = superloc::testing::freshDir("bench_app_jobs");
    const std::string tools = writeTwoSequenceSuite(d, "good lift stop", 60);
    BenchApp one, two;
    one.initialize({d + "/suite.ini", "--out", d + "/one", "--tools", tools, "--jobs", "1"});
    std::ostringstream log1, log2;
    EXPECT_EQ(one.run(log1), 0) << log1.str();
    // With two jobs, a sequence's `good` waits for another run to start beside it: they run
    // together, so the other finishes first, and the results must still come in the suite's order.
    std::ofstream(tools + "/rendezvous") << "1\n";
    two.initialize({d + "/suite.ini", "--out", d + "/two", "--tools", tools, "--jobs", "2"});
    EXPECT_EQ(two.run(log2), 0) << log2.str();
    for (const char* seq : {"plane", "hall"})
        EXPECT_EQ(slurp(d + "/two/runs/" + seq + "/good.rendezvous"), "met\n") << seq << "\n" << log2.str();

    ASSERT_EQ(one.runs.size(), 6u);
    ASSERT_EQ(two.runs.size(), one.runs.size());
    for (size_t i = 0; i < one.runs.size(); ++i) {
        EXPECT_EQ(two.runs[i].sequence, one.runs[i].sequence) << i;
        EXPECT_EQ(two.runs[i].method, one.runs[i].method) << i;
        EXPECT_EQ(two.runs[i].status, one.runs[i].status) << i;
    }
    EXPECT_EQ(one.runs[2].status, "exit 3");  // a failed child is reported the same way
    EXPECT_EQ(two.plots, one.plots);
    const std::string md1 = slurp(d + "/one/results.md"), md2 = slurp(d + "/two/results.md");
    EXPECT_EQ(resultsMarkdownWithoutTimes(md2), resultsMarkdownWithoutTimes(md1));
    EXPECT_NE(resultsMarkdownWithoutTimes(md1).find("| good | **0.00** | **0.00** |"), std::string::npos) << md1;
    EXPECT_NE(resultsMarkdownWithoutTimes(md1).find("| hall | stop | exit 3 | 6/11 |"), std::string::npos)
        << resultsMarkdownWithoutTimes(md1);
    // Only the parallel run says its times were measured on shared cores.
    EXPECT_EQ(md1.find("(--jobs)"), std::string::npos);
    EXPECT_NE(md2.find("2 runs at a time (--jobs) shared the machine's cores"), std::string::npos);
    const std::string js1 = slurp(d + "/one/results.json"), js2 = slurp(d + "/two/results.json");
    EXPECT_EQ(resultsJsonWithoutTimes(js2), resultsJsonWithoutTimes(js1));
    EXPECT_EQ(nlohmann::json::parse(js1)["jobs"], 1);
    EXPECT_EQ(nlohmann::json::parse(js2)["jobs"], 2);
    for (const char* f : {"plane_good_top.svg", "hall_lift_gamma.svg", "hall_f1_rot.svg"})
        EXPECT_EQ(slurp(d + "/two/" + f), slurp(d + "/one/" + f)) << f;
    // Every progress line is whole and names its run.
    EXPECT_NE(log2.str().find("  hall / lift: ok, ATE 0.200 m"), std::string::npos) << log2.str();
}

TEST(BenchApp, JobsKeepThePerChildTimeout) {
    const std::string d = superloc::testing::freshDir("bench_app_jobs_timeout");
    const std::string tools = writeTwoSequenceSuite(d, "hang good", 1);
    BenchApp app;
    app.initialize({d + "/suite.ini", "--out", d + "/out", "--tools", tools, "--jobs", "3"});
    std::ostringstream log;
    EXPECT_EQ(app.run(log), 2) << log.str();  // the hung runs left no trajectory
    ASSERT_EQ(app.runs.size(), 4u);
    for (size_t i : {0u, 2u}) {
        EXPECT_EQ(app.runs[i].method, "hang");
        EXPECT_EQ(app.runs[i].status, "timeout after 1 s; no trajectory") << i;
    }
    for (size_t i : {1u, 3u}) EXPECT_EQ(app.runs[i].status, "ok") << i;
}

TEST(BenchApp, BadJobsAreRejectedNamingTheFlag) {
    const std::string d = superloc::testing::freshDir("bench_app_bad_jobs");
    writeTwoSequenceSuite(d, "good", 60);
    for (const std::vector<std::string>& bad :
         {std::vector<std::string>{"--jobs", "0"}, {"--jobs", "-1"}, {"--jobs=-1"}, {"--jobs", "text"},
          {"--jobs", "2.5"}, {"--jobs", "4096"}, {"--jobs"}}) {
        std::vector<std::string> args = {d + "/suite.ini", "--out", d + "/out"};
        args.insert(args.end(), bad.begin(), bad.end());
        try {
            BenchApp().initialize(args);
            ADD_FAILURE() << bad.back() << " was accepted";
        } catch (const std::exception& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("--jobs"), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    }
    BenchApp ok;
    ok.initialize({d + "/suite.ini", "--out", d + "/out", "--jobs", "3"});
    EXPECT_EQ(ok.jobs, 3u);
    BenchApp by_default;
    by_default.initialize({d + "/suite.ini", "--out", d + "/out"});
    EXPECT_EQ(by_default.jobs, 0u);  // one per core
    EXPECT_GE(availableCores(), 1u);
}

// Two sequences that differ only in their localize settings share one simulation; --drop-data
// removes the shared data once the last of them is done, not when the first is.
TEST(BenchApp, SequencesOfTheSameDataSimulateItOnceAndDropItAfterTheLast) {
    const std::string d = superloc::testing::freshDir("bench_share");
    const std::string tools = d + "/tools";
    fs::create_directories(tools);
    writeScript(tools + "/superloc-sim", std::string(kParse) + "echo sim >> \"" + d + "/sims\"\n" + kSim);
    writeScript(tools + "/superloc-localize", std::string(kParse) + kLocalize);
    writeSimSuite(d, "[suite]\nmethods = good lift\nsequences = plane plane_noimu\n"
                     "localize_config = localize.ini\ntimeout = 60\n"
                     "[seq.plane]\ntype = sim\nconfig = world.ini\nseed = 3\n"
                     "[seq.plane_noimu]\ntype = sim\nconfig = world.ini\nseed = 3\n"
                     "localize_set = localization.use_imu=false\n");
    BenchApp app;
    app.initialize({d + "/suite.ini", "--out", d + "/out", "--tools", tools, "--jobs", "2", "--drop-data"});
    std::ostringstream log;
    EXPECT_EQ(app.run(log), 0) << log.str();
    ASSERT_EQ(app.runs.size(), 4u);
    for (const auto& r : app.runs) {
        EXPECT_EQ(r.status, "ok") << r.sequence << "/" << r.method;
        ASSERT_TRUE(r.result) << r.sequence << "/" << r.method;
    }
    EXPECT_NEAR(app.runs[3].result->ate.trans.rmse, 0.2, 1e-9);  // plane_noimu / lift
    EXPECT_EQ(slurp(d + "/sims"), "sim\n");
    EXPECT_FALSE(fs::exists(d + "/out/data/plane/sequence.rawlog"));
    EXPECT_FALSE(fs::exists(d + "/out/data/plane_noimu"));
}
