#include <gtest/gtest.h>
#include <superloc/core/config.h>
#include <superloc/app/bench_report.h>
#include <superloc/app/process.h>
#include <superloc/app/suite.h>
#include <superloc_testing/testing.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace superloc;
using namespace superloc::eval;
using namespace superloc::app;
namespace fs = std::filesystem;

namespace {
std::string write(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
    return path;
}
std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}
/// A suite folder with a localize.ini, a sim scenario and a fake data set.
std::string suiteDir(const std::string& name) {
    const std::string d = superloc::testing::freshDir(name);
    write(d + "/localize.ini", "[localization]\n");
    write(d + "/world.ini", "[sim]\n");
    fs::create_directories(d + "/data/realset/scans");
    write(d + "/data/realset/gt.txt", "0 0 0 0 0 0 0 1\n");
    return d;
}
}  // namespace

// Sequences that differ only in their localize settings (the stress sweeps' with / without IMU)
// share one simulation: the same data folder; another sim_set or seed is other data.
TEST(Suite, SequencesSimulatingTheSameDataShareIt) {
    const std::string d = suiteDir("suite_share");
    const std::string path = write(
        d + "/s.ini",
        "[suite]\nmethods = superloc\nsequences = a a_noimu b\nlocalize_config = localize.ini\n"
        "[seq.a]\ntype = sim\nconfig = world.ini\nseeds = 1 2\nsim_set = sim.duration=5\n"
        "[seq.a_noimu]\ntype = sim\nconfig = world.ini\nseeds = 1 2\nsim_set = sim.duration=5\n"
        "localize_set = localization.use_imu=false\n"
        "[seq.b]\ntype = sim\nconfig = world.ini\nseeds = 1\nsim_set = sim.duration=6\n");
    const SuiteSpec s = loadSuite(path, d + "/data");
    ASSERT_EQ(s.sequences.size(), 5u);
    EXPECT_EQ(sequenceFiles(s.sequences[2], "/o").dir, "/o/data/a_s1");  // a_noimu_s1
    EXPECT_EQ(sequenceFiles(s.sequences[3], "/o").dir, "/o/data/a_s2");  // a_noimu_s2
    EXPECT_EQ(sequenceFiles(s.sequences[1], "/o").dir, "/o/data/a_s2");
    EXPECT_EQ(sequenceFiles(s.sequences[4], "/o").dir, "/o/data/b_s1");
}

TEST(Suite, LoadsSequencesAndBuildsCommands) {
    const std::string d = suiteDir("suite_load");
    const std::string path = write(
        d + "/s.ini",
        "[suite]\nmethods = superloc icp\nsequences = w realset\nlocalize_config = localize.ini\n"
        "localize_set = localization.max_frames=50\ntimeout = 60\n"
        "[eval]\noutlier_threshold = 0.2\n"
        "[seq.w]\ntype = sim\nconfig = world.ini\nseed = 7\nsim_set = sim.duration=5 sim.rate=10\n"
        "[seq.realset]\ntype = pcd\ndata = realset\ngt = gt.txt\nprior_voxel = 0.2\n");
    const SuiteSpec s = loadSuite(path, d + "/data");
    EXPECT_EQ(s.methods, (std::vector<std::string>{"superloc", "icp"}));
    EXPECT_DOUBLE_EQ(s.timeout_s, 60);
    EXPECT_DOUBLE_EQ(s.eval.outlier_threshold, 0.2);
    ASSERT_EQ(s.sequences.size(), 2u);
    const SequenceSpec& w = s.sequences[0];
    EXPECT_EQ(w.kind, SequenceSpec::Kind::Sim);
    EXPECT_EQ(w.seed, 7);
    EXPECT_EQ(simCommand("sim", w, "OUT"),
              (std::vector<std::string>{"sim", w.config, "--out", "OUT", "--seed", "7", "--set",
                                        "sim.duration=5", "--set", "sim.rate=10"}));
    const SequenceSpec& r = s.sequences[1];
    EXPECT_EQ(r.kind, SequenceSpec::Kind::PcdDir);
    EXPECT_EQ(fs::path(r.scans).filename(), "scans");
    EXPECT_DOUBLE_EQ(r.prior_voxel, 0.2);
    EXPECT_EQ(importCommand("imp", r, "x.rawlog"),
              (std::vector<std::string>{"imp", "--pcd-dir", r.scans, "--poses", r.gt, "--out",
                                        "x.rawlog", "--quiet"}));
    EXPECT_EQ(mapCommand("map", "x.rawlog", "gt.txt", 0.05, "m.pcd"),
              (std::vector<std::string>{"map", "--rawlog", "x.rawlog", "--poses", "gt.txt",
                                        "--voxel", "0.05", "--out", "m.pcd"}));
    const SequenceFiles f = sequenceFiles(w, "/o");
    EXPECT_EQ(f.rawlog, "/o/data/w/sequence.rawlog");
    EXPECT_EQ(f.gt_map, "/o/data/w/gt_map.ply");
    EXPECT_EQ(sequenceFiles(r, "/o").gt_tum, r.gt);
    const auto loc = localizeCommand("loc", s, w, "icp", f, "/o/runs/w/icp");
    EXPECT_EQ(joinCommand(loc),
              "loc " + s.localize_config +
                  " --rawlog /o/data/w/sequence.rawlog --map /o/data/w/prior_map.pcd --method icp"
                  " --out /o/runs/w/icp --initial-pose-tum /o/data/w/gt_tum.txt --quiet --set "
                  "localization.max_frames=50");
}

TEST(Suite, BadSuitesNameFileSectionAndKey) {
    const std::string d = suiteDir("suite_bad");
    auto fails = [&](const std::string& text, const std::string& expect) {
        const std::string path = write(d + "/bad.ini", text);
        try {
            loadSuite(path, d + "/data");
            ADD_FAILURE() << "no error for: " << text;
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
        }
    };
    const std::string head = "[suite]\nmethods = icp\nlocalize_config = localize.ini\n";
    fails(head + "sequences = a\n", "no [seq.a]");
    fails(head + "sequences = a\n[seq.a]\ntype = sim\nconfig = world.ini\nsed = 3\n",
          "unknown key 'sed' in section [seq.a]");
    fails(head + "sequences = a\n[seq.a]\ntype = sim\nconfig = nothere.ini\n",
          "nothere.ini does not exist");
    fails(head + "sequences = a\n[seq.a]\ntype = lidar\n", "expected sim, kitti or pcd");
    fails(head + "sequences = a\n[seq.a]\ntype = sim\nconfig = world.ini\nseed = x\n",
          "is not a number");
    fails("[suite]\nmethods = icp\nsequences = a\n", "localize_config is required");
    fails(head + "sequences = a\n[eval]\nmap_voxl = 1\n[seq.a]\ntype = sim\nconfig = world.ini\n",
          "unknown key 'map_voxl'");
}

TEST(Process, ExitCodesLogsAndTimeout) {
    const std::string d = superloc::testing::freshDir("eval_process");
    const ProcessResult ok = runProcess({"/bin/sh", "-c", "echo hello; exit 0"}, d + "/a.log", 10);
    EXPECT_TRUE(ok.ok());
    EXPECT_EQ(slurp(d + "/a.log"), "hello\n");
    const ProcessResult bad =
        runProcess({"/bin/sh", "-c", "echo oops >&2; exit 3"}, d + "/b.log", 10);
    EXPECT_EQ(bad.exit_code, 3);
    EXPECT_FALSE(bad.ok());
    EXPECT_EQ(slurp(d + "/b.log"), "oops\n");
    const ProcessResult slow = runProcess({"/bin/sh", "-c", "exec sleep 30"}, d + "/c.log", 0.3);
    EXPECT_TRUE(slow.timed_out);
    EXPECT_EQ(slow.exit_code, 128 + 9);
    EXPECT_FALSE(runProcess({d + "/no-such-tool"}, d + "/d.log", 10).started);
    EXPECT_EQ(findTool("sh", "/nonexistent"), fs::path(findTool("sh", "/nonexistent")).string());
    EXPECT_EQ(findTool("superloc-no-such-tool", d), "");
}

// The peak memory is the child program's own: not the parent's, which a forked child shares
// until its exec (rusage's ru_maxrss counts it: a 300 MiB parent made every child 300 MiB).
TEST(Process, PeakMemoryIsTheChildProgramsOwn) {
    const std::string d = superloc::testing::freshDir("eval_process_memory");
    std::vector<char> parent(300u << 20);
    for (size_t i = 0; i < parent.size(); i += 4096) parent[i] = static_cast<char>(i >> 12);
    const ProcessResult small = runProcess({"/bin/sh", "-c", "exec sleep 0.3"}, d + "/a.log", 10);
    ASSERT_TRUE(small.ok());
    EXPECT_GT(small.peak_rss_mb, 0.0);
    EXPECT_LT(small.peak_rss_mb, 50.0);
    // A child that holds 200 MiB for a while (python3 is a build dependency).
    const ProcessResult big = runProcess(
        {"/usr/bin/python3", "-c", "import time; b = bytearray(200 << 20); time.sleep(0.3)"},
        d + "/b.log", 30);
    ASSERT_TRUE(big.ok()) << slurp(d + "/b.log");
    EXPECT_GT(big.peak_rss_mb, 200.0);
    EXPECT_LT(big.peak_rss_mb, 290.0);
    EXPECT_NE(parent[4096], 5);  // keeps the parent's pages alive until here
}

TEST(BenchReport, TableShapeBestValuesAndFailures) {
    auto run = [](const std::string& seq, const std::string& m, double ate, double out,
                  const std::string& st) {
        RunRecord r;
        r.sequence = seq, r.method = m, r.status = st, r.gt_length_m = 100;
        EvalResult e;
        e.matched_frames = 10;
        e.ate.trans.rmse = ate;
        e.rp.area = 0.9;
        MapResult map;
        map.outlier_percent = out;
        map.threshold = 0.1;
        e.map = map;
        r.result = e;
        return r;
    };
    std::vector<RunRecord> runs = {
        run("cave", "superloc", 0.05, 1.5, "ok"), run("cave", "icp", 0.5, 30, "ok"),
        run("corridor", "superloc", 0.1, 3.55, "ok"), run("corridor", "icp", 9, 80, "exit 3")};
    const std::string md =
        resultsMarkdown(runs, {"cave", "corridor"}, {"superloc", "icp"}, "cmd\n");
    EXPECT_NE(md.find("## Map outliers [%] (farther than 10 cm from the GT map)"),
              std::string::npos)
        << md;
    EXPECT_NE(md.find("| Method | cave | corridor |"), std::string::npos);
    EXPECT_NE(md.find("| Distance [m] | 100 | 100 |"), std::string::npos);
    EXPECT_NE(md.find("| superloc | **1.50** | **3.55** |"), std::string::npos) << md;
    EXPECT_NE(md.find("| icp | 30.00 | 80.00 † |"), std::string::npos) << md;
    EXPECT_NE(md.find("- corridor / icp: exit 3"), std::string::npos);
    const std::string js = resultsJson(runs, "s.ini");
    EXPECT_NE(js.find("\"status\": \"exit 3\""), std::string::npos);
    Trajectory t = {{0, SE3d::Identity(), {}}, {1, SE3d(Eigen::Translation3d(3, 4, 0)), {}}};
    EXPECT_DOUBLE_EQ(pathLength(t), 5.0);
}

// The committed suites parse and name existing files (the sim scenarios, the localizer INI,
// the real data sets).
TEST(Suite, CommittedSuitesLoad) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    if (!fs::exists(superloc::testing::sourcePath("ini/localize.ini")))
        GTEST_SKIP() << "ini/localize.ini not in this tree yet";
    const SuiteSpec quick = loadSuite(superloc::testing::sourcePath("ini/bench/quick.ini"),
                                      superloc::testing::sharedData());
    EXPECT_EQ(quick.sequences.size(), 3u);
    const SuiteSpec paper = loadSuite(superloc::testing::sourcePath("ini/bench/paper.ini"),
                                      superloc::testing::sharedData());
    EXPECT_EQ(paper.methods,
              (std::vector<std::string>{"superloc", "superloc_paper", "icp", "passive", "eigen_remap", "ndt"}));
    ASSERT_EQ(paper.sequences.size(), 8u);
    EXPECT_EQ(paper.sequences[1].name, "corridor-long");
    EXPECT_EQ(paper.sequences[1].sim_sets,
              (std::vector<std::string>{"corridor.length=300", "corridor.recesses=0", "sim.duration=150"}));
    EXPECT_EQ(paper.sequences[6].kind, SequenceSpec::Kind::PcdDir);
    EXPECT_EQ(paper.sequences[7].localize_sets,
              (std::vector<std::string>{"features.deskew=false"}));
    // Every other committed suite (the stress studies) loads too.
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(superloc::testing::sourcePath("ini/bench"))) {
        if (e.path().extension() != ".ini") continue;
        const SuiteSpec s = loadSuite(e.path().string(), superloc::testing::sharedData());
        EXPECT_FALSE(s.sequences.empty()) << e.path();
        EXPECT_FALSE(s.methods.empty()) << e.path();
        ++n;
    }
    EXPECT_GE(n, 10u);
}
