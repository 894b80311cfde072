// superloc-eval's app class on the real kitti00-mini ground truth (issue 6 "must show").
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <superloc/core/config.h>
#include <superloc/app/eval_app.h>
#include <superloc/io/tum.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

using namespace superloc;
using namespace superloc::eval;
using namespace superloc::app;

namespace {
std::string runApp(const std::vector<std::string>& args, int* rc = nullptr) {
    EvalApp app;
    app.initialize(args);
    std::ostringstream out;
    const int code = app.run(out);
    if (rc) *rc = code;
    return out.str();
}
std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}
}  // namespace

TEST(EvalApp, KittiGtAgainstItselfIsExact) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    const std::string gt = superloc::testing::sharedData("kitti00-mini/gt_velodyne_tum.txt");
    const std::string dir = superloc::testing::freshDir("eval_app_kitti");
    int rc = -1;
    const std::string out =
        runApp({"--est", gt, "--gt", gt, "--json", dir + "/r.json", "--plots", dir}, &rc);
    EXPECT_EQ(rc, 0);
    EXPECT_NE(out.find("| 16 / 16 / 16 |"), std::string::npos) << out;
    EXPECT_NE(out.find("0.0000 / 0.0000 / 0.0000"), std::string::npos) << out;
    EXPECT_NE(out.find("| Rp / Rr | 1.0000 / 1.0000 |"), std::string::npos) << out;
    const auto json = nlohmann::json::parse(slurp(dir + "/r.json"));
    EXPECT_EQ(json["matched_frames"].get<int>(), 16);
    EXPECT_NEAR(json["Rp"].get<double>(), 1 - std::exp(-10.0), 1e-6);
    EXPECT_NEAR(json["ate"]["trans_m"]["rmse"].get<double>(), 0.0, 1e-9);
    EXPECT_EQ(json["f1_trans"]["tau"].size(), json["f1_trans"]["f1"].size());
    EXPECT_TRUE(std::filesystem::exists(dir + "/trajectory.svg"));
    EXPECT_TRUE(std::filesystem::exists(dir + "/f1_rot.svg"));
}

TEST(EvalApp, KittiShiftedBy30cmHasAte30cm) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    const std::string gt = superloc::testing::sharedData("kitti00-mini/gt_velodyne_tum.txt");
    const std::string dir = superloc::testing::freshDir("eval_app_kitti_shift");
    Trajectory shifted = io::loadTum(gt);
    for (auto& p : shifted) p.pose.pretranslate(Vec3d(0.3, 0, 0));
    io::saveTum(dir + "/shifted.tum", shifted);
    const std::string out =
        runApp({"--est", dir + "/shifted.tum", "--gt", gt, "--json", dir + "/r.json"});
    EXPECT_NE(out.find("| 0.3000 / 0.3000 / 0.3000 |"), std::string::npos) << out;
    const auto json = nlohmann::json::parse(slurp(dir + "/r.json"));
    EXPECT_NEAR(json["ate"]["trans_m"]["rmse"].get<double>(), 0.3, 1e-6);
    EXPECT_NEAR(json["ate"]["trans_m"]["max"].get<double>(), 0.3, 1e-6);
    EXPECT_EQ(json["aligned"], false);
    // Aligned, the rigid shift disappears.
    const std::string al = runApp({"--est", dir + "/shifted.tum", "--gt", gt, "--align"});
    EXPECT_NE(al.find("(SE(3)-aligned) | 0.0000"), std::string::npos) << al;
}

// With --frames, the risk table: the estimate is the GT shifted 0.3 m along the map's x on
// frames 0-7 (16 frames); a frames.csv flags "x" (both label rules) on frames 0-3 and 8, nothing
// by the eigen rule. The error is read in each GT pose's own axes, so whether it lands on body x
// depends on the heading; the counts must add up to what the error along body x says per frame.
TEST(EvalApp, FramesGiveTheRiskPredictionTable) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    const std::string gt = superloc::testing::sharedData("kitti00-mini/gt_velodyne_tum.txt");
    const std::string dir = superloc::testing::freshDir("eval_app_kitti_risk");
    const Trajectory truth = io::loadTum(gt);
    Trajectory est = truth;
    for (size_t i = 0; i < 8; ++i) est[i].pose.pretranslate(Vec3d(0.3, 0, 0));
    io::saveTum(dir + "/est.tum", est);
    {
        std::ofstream f(dir + "/frames.csv");
        f << "t,ms_total,flags_labels1,flags_labels2,flags_eigen,degenerate\n";
        for (size_t i = 0; i < est.size(); ++i) {
            const char* flag = i < 4 || i == 8 ? "x" : "";
            const char* weak = i < 8 ? "x" : "";  // the estimate's decision: every failed frame
            f << std::setprecision(17) << est[i].t << ",5," << flag << "," << flag << ",," << weak << "\n";
        }
    }
    // Expected by hand from the geometry: frame i failed along body x when
    // |(R_gt^T (0.3, 0, 0)).x| > 0.1 m.
    size_t tp = 0, fp = 0, fn = 0;
    for (size_t i = 0; i < est.size(); ++i) {
        const bool failed = i < 8 && std::abs((truth[i].pose.linear().transpose() * Vec3d(0.3, 0, 0)).x()) > 0.1;
        const bool flagged = i < 4 || i == 8;
        tp += flagged && failed, fp += flagged && !failed, fn += !flagged && failed;
    }
    ASSERT_GT(tp, 0u);
    const std::string out = runApp({"--est", dir + "/est.tum", "--gt", gt, "--frames", dir + "/frames.csv",
                                    "--json", dir + "/r.json"});
    EXPECT_NE(out.find("Risk as a failure predictor (16 frames"), std::string::npos) << out;
    const auto json = nlohmann::json::parse(slurp(dir + "/r.json"));
    const auto& x = json["risk_prediction"]["flags_labels2"]["x"];
    EXPECT_EQ(x["tp"].get<size_t>(), tp);
    EXPECT_EQ(x["fp"].get<size_t>(), fp);
    EXPECT_EQ(x["fn"].get<size_t>(), fn);
    EXPECT_EQ(json["risk_prediction"]["flags_eigen"]["x"]["tp"].get<size_t>(), 0u);
    const auto& d = json["risk_prediction"]["degenerate"]["x"];
    EXPECT_EQ(d["tp"].get<size_t>() + d["fn"].get<size_t>(), tp + fn);
    EXPECT_EQ(d["fn"].get<size_t>(), 0u);
}

TEST(EvalApp, BadCommandLinesAreOneLineErrors) {
    EvalApp a;
    EXPECT_THROW(a.initialize({"--gt", "x.tum"}), std::invalid_argument);
    EXPECT_THROW(EvalApp().initialize({"--est", "a", "--gt", "b", "--est-map", "m.pcd"}),
                 ConfigError);  // --est-map needs --gt-map
    EXPECT_THROW(EvalApp().initialize({"--bogus"}), ConfigError);
    EXPECT_THROW(EvalApp().initialize({"--est"}), superloc::ConfigError);  // missing value
    EXPECT_THROW(EvalApp().initialize({"--est", "a", "--gt", "b", "--set", "eval.nokey=1"}),
                 ConfigError);
    EvalApp missing;
    missing.initialize({"--est", "/nonexistent.tum", "--gt", "/nonexistent.tum"});
    std::ostringstream out;
    EXPECT_THROW(missing.run(out), std::runtime_error);
    int rc = -1;
    EXPECT_NE(runApp({"--help"}, &rc).find("Usage: superloc-eval"), std::string::npos);
    EXPECT_EQ(rc, 0);
    EXPECT_NE(
        runApp({"--dump-config", "--set", "eval.outlier_threshold=0.2"}).find("outlier_threshold"),
        std::string::npos);
}
