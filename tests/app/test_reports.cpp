#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <superloc/core/se3.h>
#include <superloc/eval/frame_log.h>
#include <superloc/eval/evaluation.h>
#include <superloc/io/json_file.h>
#include <superloc/app/report_plots.h>
#include <superloc/app/run_outputs.h>
#include <superloc/app/svg_plot.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <fstream>
#include <limits>

using namespace superloc;
using namespace superloc::eval;
using namespace superloc::app;

TEST(EvalJson, EveryMetricParsesBackNonFiniteAsNull) {
    EvalResult r;
    r.est_frames = r.gt_frames = r.matched_frames = 3;
    r.ate.trans.n = 3;
    r.ate.trans.rmse = 0.25;
    r.ate.rot.rmse = std::numeric_limits<double>::infinity();  // e.g. a 1e300 m estimate
    r.rp.area = 0.5;
    r.rp.curve.resize(2);
    r.rp.curve[0].tau = 0.1;
    r.rp.curve[0].f1 = 0.2;
    r.rp.curve[1].tau = 0.5;
    r.rp.curve[1].f1 = 0.9;
    r.timing = TimingStats{};
    r.timing->median_ms = 12.5;
    r.degenerate_frame_percent = std::nan("");
    const auto j = nlohmann::json::parse(io::toJsonText(toJson(r), "test"));
    EXPECT_EQ(j["matched_frames"].get<int>(), 3);
    EXPECT_NEAR(j["ate"]["trans_m"]["rmse"].get<double>(), 0.25, 1e-12);
    EXPECT_TRUE(j["ate"]["rot_rad"]["rmse"].is_null());
    EXPECT_NEAR(j["Rp"].get<double>(), 0.5, 1e-12);
    ASSERT_EQ(j["f1_trans"]["tau"].size(), 2u);
    EXPECT_NEAR(j["f1_trans"]["f1"][1].get<double>(), 0.9, 1e-12);
    EXPECT_NEAR(j["timing"]["median_ms"].get<double>(), 12.5, 1e-12);
    EXPECT_TRUE(j["degenerate_frame_percent"].is_null());
    EXPECT_FALSE(j.contains("map"));
    EXPECT_FALSE(nlohmann::json::parse(io::toJsonText(toJson(r, false))).contains("f1_trans"));
}

TEST(FrameLog, ParsesDegenerateLetters) {
    const auto f = parseDegenerateAxes("xyaw");
    EXPECT_EQ(f, (std::array<bool, 6>{true, false, false, false, false, true}));
    EXPECT_EQ(parseDegenerateAxes("rollpitchz"),
              (std::array<bool, 6>{false, false, true, true, true, false}));
    EXPECT_EQ(parseDegenerateAxes(""), (std::array<bool, 6>{}));
    EXPECT_THROW(parseDegenerateAxes("xq"), std::invalid_argument);
}

TEST(FrameLog, ReadsTheLocalizerCsv) {
    const std::string dir = superloc::testing::freshDir("eval_frame_log");
    const std::string path = dir + "/frames.csv";
    {
        std::ofstream f(path);
        f << "t,x,y,z,qx,qy,qz,qw,gamma_x,gamma_y,gamma_z,gamma_roll,gamma_pitch,gamma_yaw,"
             "degenerate,prior_used,ms_total,ms_solve\n"
          << "1.0,0,0,0,0,0,0,1,0.1,1,1,0.9,0.8,0.05,xyaw,1,12.5,7\n"
          << "1.1,0,0,0,0,0,0,1,1,1,1,1,1,1,,0,10,5\n";
    }
    const FrameLog log = loadFrameLog(path);
    ASSERT_EQ(log.frames.size(), 2u);
    EXPECT_TRUE(log.has_gamma);
    EXPECT_DOUBLE_EQ(log.frames[0].gamma[0], 0.1);
    EXPECT_DOUBLE_EQ(log.frames[0].gamma[5], 0.05);
    EXPECT_TRUE(log.frames[0].degenerate[0] && log.frames[0].degenerate[5]);
    EXPECT_FALSE(log.frames[1].degenerate[0]);
    EXPECT_EQ(log.stage_ms.at("ms_solve"), (std::vector<double>{7, 5}));
    EXPECT_DOUBLE_EQ(log.frames[1].ms_total, 10.0);

    // min translation gamma per pose, by time
    Trajectory tr = {
        {1.0, SE3d::Identity(), {}}, {1.1, SE3d::Identity(), {}}, {5.0, SE3d::Identity(), {}}};
    const auto g = minTranslationGamma(tr, log, 0.02);
    EXPECT_DOUBLE_EQ(g[0], 0.1);
    EXPECT_DOUBLE_EQ(g[1], 1.0);
    EXPECT_TRUE(std::isnan(g[2]));
}

// The three rule columns (flags_labels1, flags_labels2, flags_eigen) are read when all are
// there; an unknown letter names the column.
TEST(FrameLog, ReadsTheRuleColumns) {
    const std::string dir = superloc::testing::freshDir("eval_frame_log_rules");
    const std::string path = dir + "/frames.csv";
    {
        std::ofstream(path) << "t,ms_total,flags_labels1,flags_labels2,flags_eigen,degenerate\n"
                            << "1,10,xyaw,x,,z\n2,10,,,rollpitch,\n";
    }
    const FrameLog log = loadFrameLog(path);
    ASSERT_TRUE(log.has_rules);
    ASSERT_EQ(log.frames.size(), 2u);
    EXPECT_EQ(log.frames[0].rule_flags[0], parseDegenerateAxes("xyaw"));
    EXPECT_EQ(log.frames[0].rule_flags[1], parseDegenerateAxes("x"));
    EXPECT_EQ(log.frames[0].rule_flags[2], parseDegenerateAxes(""));
    EXPECT_EQ(log.frames[1].rule_flags[2], parseDegenerateAxes("rollpitch"));
    // The fourth rule is the frame's decision, `degenerate` (the estimate's weak axes).
    EXPECT_EQ(log.frames[0].rule_flags[3], parseDegenerateAxes("z"));
    EXPECT_EQ(log.frames[1].rule_flags[3], parseDegenerateAxes(""));
    { std::ofstream(path) << "t,ms_total,flags_labels1,flags_labels2,flags_eigen,degenerate\n1,10,x,q,,\n"; }
    try {
        loadFrameLog(path);
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(path + ":2: column 'flags_labels2'"), std::string::npos) << e.what();
    }
}

TEST(FrameLog, ErrorsNameFileAndLine) {
    const std::string dir = superloc::testing::freshDir("eval_frame_log_bad");
    const std::string path = dir + "/frames.csv";
    { std::ofstream(path) << "t,ms_total\n1.0,abc\n"; }
    try {
        loadFrameLog(path);
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(path + ":2: column 'ms_total'"), std::string::npos)
            << e.what();
    }
    { std::ofstream(path) << "time,ms\n"; }
    EXPECT_THROW(loadFrameLog(path), std::runtime_error);
    EXPECT_THROW(loadFrameLog(dir + "/missing.csv"), std::runtime_error);
}

TEST(Svg, PlotsAreCompleteDocuments) {
    Trajectory gt, est;
    for (int i = 0; i < 10; ++i) {
        gt.push_back({0.1 * i, makePoseRPY(i, 0.1 * i * i, 0, 0, 0, 0), {}});
        est.push_back({0.1 * i, makePoseRPY(i, 0.1 * i * i + 0.05, 0, 0, 0, 0), {}});
    }
    const std::string top = trajectoryTopViewSvg(gt, est, std::vector<double>(10, 0.5), "a<b");
    EXPECT_EQ(top.rfind("<?xml", 0), 0u);
    EXPECT_NE(top.find("</svg>"), std::string::npos);
    EXPECT_NE(top.find("a&lt;b"), std::string::npos);
    EXPECT_NE(top.find(gammaColor(0.5)), std::string::npos);
    FrameLog log;
    for (int i = 0; i < 10; ++i) {
        FrameRecord f;
        f.t = 0.1 * i;
        f.gamma.setConstant(1);
        f.gamma[0] = i < 5 ? 0.1 : 1;
        f.degenerate[0] = i < 5;
        log.frames.push_back(f);
    }
    const std::string g = gammaTimelineSvg(log, 0.2, "gamma");
    EXPECT_NE(g.find("fill=\"#d62728\""), std::string::npos);  // shaded degenerate span
    RobustnessCurve c;
    c.curve = {{1.0, 1, 1, 1}, {0.1, 1, 1, 0.5}};
    EXPECT_NE(f1CurvesSvg({{"m", c}}, false, "F1").find("<polyline"), std::string::npos);
    EXPECT_EQ(gammaColor(0), "hsl(0,85%,42%)");
    EXPECT_EQ(gammaColor(1), "hsl(120,85%,42%)");
}

// A free-text column with a comma shifts the later columns: stage times of that row are
// skipped, the leading columns still count.
TEST(FrameLog, ShiftedRowsKeepLeadingColumns) {
    const std::string dir = superloc::testing::freshDir("eval_frame_log_shift");
    const std::string path = dir + "/frames.csv";
    { std::ofstream(path) << "t,ms_total,reason,ms_solve\n1,10,fine,4\n2,12,a,b,5\n"; }
    const FrameLog log = loadFrameLog(path);
    EXPECT_EQ(log.stage_ms.at("ms_total"), (std::vector<double>{10, 12}));
    EXPECT_EQ(log.stage_ms.at("ms_solve"), (std::vector<double>{4}));
}

// summary.json's frame figures from RunTally: counts at once, then the ATE against the GT
// interpolated at each frame's time (a frame 0.3 m off and one on the track: RMSE sqrt(0.045)),
// a frame beyond the GT's reach unmatched, and the pose sigmas of the frames not lost only.
TEST(RunTally, CountsSigmasAndAteAgainstInterpolatedGroundTruth) {
    app::RunTally tally;
    app::RunSummary s;
    for (double t : {0.0, 1.0, 2.0}) tally.addGroundTruth({t, makePoseRPY(t, 0, 0, 0, 0, 0), std::nullopt});
    const auto frame = [](double t, localization::Health h, double sigma) {
        localization::FrameReport r;
        r.t = t;
        r.health = h;
        r.ms.total = r.ms.total_cpu = 10 * t + 1;
        r.cov = Mat6d::Identity() * sigma * sigma;
        return r;
    };
    tally.addFrame(frame(0.5, localization::Health::Ok, 0.1), makePoseRPY(0.5, 0.3, 0, 0, 0, 0), s);
    tally.addFrame(frame(1.5, localization::Health::Degraded, 0.2), makePoseRPY(1.5, 0, 0, 0, 0, 0), s);
    tally.addFrame(frame(9.0, localization::Health::Lost, 5.0), makePoseRPY(9, 0, 0, 0, 0, 0), s);
    EXPECT_EQ(s.frames, 3u);
    EXPECT_EQ(s.health[0], 1u);
    EXPECT_EQ(s.health[1], 1u);
    EXPECT_EQ(s.health[2], 1u);
    tally.fill(s);
    EXPECT_EQ(s.gt_matched, 2u);
    EXPECT_NEAR(s.ate_rmse, std::sqrt(0.09 / 2), 1e-9);
    EXPECT_NEAR(s.ate_max, 0.3, 1e-9);
    EXPECT_NEAR(s.sigma_xyz[2], 0.2, 1e-9);  // the lost frame's 5 m left out
    EXPECT_NEAR(s.ms_median, 16.0, 1e-9);    // 6, 16, 91
}
