// End to end with IMU on sequences made by superloc-sim (when built), checked against the
// simulator's ground truth: a 3 s office (tracking) and a featureless corridor (active fusion).
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/io/tum.h>
#include <superloc/localization/localize_app.h>
#include <superloc_testing/testing.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

using namespace superloc;
using namespace superloc::localization;
namespace fs = std::filesystem;

namespace {
struct SimRun {
    RunSummary summary;
    double ate = 0, worst = 0, worst_deg = 0;  ///< against the simulator's GT
};

/// superloc-sim CONFIG --out DIR/seq with --set overrides; false when the tool is not built.
bool simulate(const std::string& dir, const std::string& config, const std::vector<std::string>& sets) {
    const std::string sim = std::string(SUPERLOC_BINARY_DIR) + "/bin/superloc-sim";
    if (!fs::exists(sim)) return false;
    std::string cmd = sim + " " + superloc::testing::sourcePath(config) + " --out " + dir + "/seq";
    for (const auto& s : sets) cmd += " --set " + s;
    cmd += " > " + dir + "/sim.log 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return true;
}

/// ini/localize.ini on DIR/seq from the GT start with `method`, into DIR/<method>.
SimRun localize(const std::string& dir, const std::string& method) {
    SimRun out;
    LocalizeApp app;
    EXPECT_EQ(app.initialize(std::vector<std::string>{
                  superloc::testing::sourcePath("ini/localize.ini"), "--rawlog", dir + "/seq/sequence.rawlog",
                  "--map", dir + "/seq/prior_map.pcd", "--initial-pose-tum", dir + "/seq/gt_tum.txt",
                  "--method", method, "--out", dir + "/" + method, "--quiet"}),
              LocalizeApp::Action::Run);
    EXPECT_EQ(app.run(), 0);
    out.summary = app.summary();
    const Trajectory gt = io::loadTum(dir + "/seq/gt_tum.txt");
    const Trajectory est = io::loadTum(dir + "/" + method + "/trajectory.tum");
    EXPECT_EQ(est.size(), out.summary.frames);
    double se = 0;
    for (const auto& e : est) {
        const auto g = interpolateAt(gt, e.t, 1.0, 1e-3);
        if (!g) {
            ADD_FAILURE() << "no GT at " << e.t;
            continue;
        }
        const double d = translationDistance(*g, e.pose);
        se += d * d;
        out.worst = std::max(out.worst, d);
        out.worst_deg = std::max(out.worst_deg, rotationAngle(*g, e.pose) * 180 / M_PI);
    }
    out.ate = est.empty() ? 0 : std::sqrt(se / static_cast<double>(est.size()));
    return out;
}
}  // namespace

TEST(LocalizeSim, OfficeWithImuTracksGroundTruth) {
    const std::string dir = superloc::testing::freshDir("e2e_sim_office");
    if (!simulate(dir, "ini/sim/office.ini", {"sim.duration=3"})) GTEST_SKIP() << "superloc-sim not built";
    const SimRun r = localize(dir, "superloc");
    const RunSummary& s = r.summary;
    EXPECT_GE(s.frames, 25u);
    EXPECT_EQ(s.used_imu, s.frames - 1) << "every frame after the first predicted with the IMU";
    EXPECT_EQ(s.diverged, 0u);
    EXPECT_LT(r.worst_deg, 1.0);
    EXPECT_LT(r.ate, 0.03) << "ATE RMSE [m]";
    EXPECT_LT(r.worst, 0.10) << "worst frame [m]";
    std::cout << "sim office 3 s with IMU: ATE " << r.ate << " m, worst " << r.worst << " m\n";
}

// The paper's claim end to end, with the IMU on: 30 s down a 150 m corridor with no door
// recesses (VLP-16). The scan says nothing along x for ~25 s; icp's x is dragged by the scan's
// spurious x information (map voxels, plane edges) and drifts by metres, superloc flags x and
// takes it from the drifting odom_alt (2 %/m). Measured: icp ATE 1.10 m, superloc 0.068 m.
TEST(LocalizeSim, FeaturelessCorridorSuperlocHoldsWhereIcpDrifts) {
    const std::string dir = superloc::testing::freshDir("e2e_sim_corridor");
    if (!simulate(dir, "ini/sim/corridor.ini",
                  {"corridor.length=150", "corridor.recesses=0", "sim.duration=30",
                   "lidar.preset=../sensors/vlp16.ini"}))
        GTEST_SKIP() << "superloc-sim not built";
    const SimRun icp = localize(dir, "icp");
    const SimRun sl = localize(dir, "superloc");
    EXPECT_GE(sl.summary.frames, 290u);
    EXPECT_EQ(sl.summary.diverged, 0u);
    EXPECT_LT(sl.ate, 0.15) << "superloc ATE RMSE [m]";
    EXPECT_LT(sl.worst, 0.4) << "superloc worst frame [m]";
    EXPECT_GT(icp.ate, 3 * sl.ate) << "icp ATE RMSE [m]: the corridor should degrade it";
    // The run summary counts what the risk step did: superloc fused odom_alt on every flagged
    // frame but the first, icp on none (its flags are reported all the same).
    EXPECT_GE(sl.summary.flagged_axis[0], 250u);
    EXPECT_EQ(sl.summary.with_prior, sl.summary.frames - 1);
    EXPECT_LE(sl.summary.flagged_without_prior, 1u);
    EXPECT_EQ(icp.summary.with_prior, 0u);
    EXPECT_EQ(icp.summary.flagged_without_prior, icp.summary.flagged);
    EXPECT_GE(icp.summary.flagged, 250u);

    // frames.csv inside the corridor (10 m < x < 140 m): x flagged, superloc's prior on x only,
    // and the classic analysis agrees: the weakest translation direction is the corridor axis.
    std::ifstream csv(dir + "/superloc/frames.csv");
    std::string line;
    ASSERT_TRUE(std::getline(csv, line));
    std::map<std::string, size_t> col;
    {
        std::stringstream ss(line);
        for (std::string name; std::getline(ss, name, ',');) col[name] = col.size();
    }
    for (const char* c : {"x", "degenerate", "prior_w_x", "prior_w_y", "weak_t_x", "trans_eig_1"})
        ASSERT_TRUE(col.count(c)) << c;
    size_t inside = 0, flagged = 0, prior_x_only = 0, weak_along_x = 0;
    while (std::getline(csv, line)) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string v; std::getline(ss, v, ',');) f.push_back(v);
        ASSERT_GT(f.size(), col["trans_eig_1"]) << line;
        const double x = std::stod(f[col["x"]]);
        if (x < 10 || x > 140) continue;
        inside++;
        flagged += f[col["degenerate"]] == "x";
        prior_x_only += std::stod(f[col["prior_w_x"]]) > 0 && std::stod(f[col["prior_w_y"]]) == 0;
        weak_along_x += std::abs(std::stod(f[col["weak_t_x"]])) > 0.95 && std::stod(f[col["trans_eig_1"]]) < 0.05;
    }
    EXPECT_GT(inside, 200u);
    EXPECT_GE(flagged, inside * 95 / 100);  // measured: 261 of 261
    EXPECT_GE(prior_x_only, inside * 95 / 100);
    EXPECT_GE(weak_along_x, inside * 95 / 100);  // measured: 258 of 261 (share median 0.008)
    std::cout << "sim featureless corridor 30 s: ATE icp " << icp.ate << " m, superloc " << sl.ate << " m\n";
}
