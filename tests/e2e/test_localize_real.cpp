// Localization on real data without IMU: campus-ouster scans 11..18 (a walk turning by 17-52 deg
// between scans taken 1 s apart) on a map built from the same scans at their ground-truth poses.
// The constant-velocity prediction is tens of degrees off in the turns; the yaw-hypothesis
// recovery (LocalizationParams::recovery_*) keeps every frame on the ground truth, and the same
// run without it loses track.
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/io/importers.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>
#include <superloc/map/map_builder.h>
#include <superloc_testing/testing.h>

#include <algorithm>
#include <filesystem>

#include "e2e_run.h"

using namespace superloc;
using namespace superloc::localization;
namespace fs = std::filesystem;

namespace {
constexpr size_t kFirst = 11, kCount = 8;

class CampusTurns : public ::testing::Test {
 protected:
    static void SetUpTestSuite() {
        dir_ = superloc::testing::freshDir("localize_real_campus");
        if (!fs::exists(superloc::testing::sharedData("campus-ouster/gt_tum.txt"))) return;  // tests skip
        const fs::path scans = superloc::testing::sharedData("campus-ouster/scans");
        std::vector<fs::path> files;
        for (const auto& e : fs::directory_iterator(scans)) files.push_back(e.path());
        std::sort(files.begin(), files.end());
        const Trajectory all = io::loadTum(superloc::testing::sharedData("campus-ouster/gt_tum.txt"));
        Trajectory gt;
        fs::create_directories(dir_ + "/scans");
        for (size_t i = kFirst; i < kFirst + kCount; ++i) {
            fs::create_symlink(files.at(i), dir_ + "/scans/" + files[i].filename().string());
            gt.push_back(all.at(i));
        }
        io::saveTum(dir_ + "/gt.tum", gt);
        io::importPcdFolder(dir_ + "/scans", dir_ + "/gt.tum", "", dir_ + "/campus.rawlog");
        map::MapBuildOptions o;
        o.rawlog = dir_ + "/campus.rawlog";
        o.poses_tum = dir_ + "/gt.tum";
        o.voxel = 0.1;
        map::MapBuilder b(o);
        PointCloud m = b.build();
        io::savePointCloud(dir_ + "/map.pcd", m);
    }

    static superloc::testing::LocalizeRun localize(const std::string& name, const std::vector<std::string>& sets) {
        std::vector<std::string> args = {"--rawlog", dir_ + "/campus.rawlog", "--map", dir_ + "/map.pcd",
                                         "--initial-pose-tum", dir_ + "/gt.tum", "--method", "icp",
                                         // already motion-compensated scans (bundle-adjusted)
                                         "--set", "features.deskew=false"};
        for (const auto& s : sets) args.insert(args.end(), {"--set", s});
        auto r = superloc::testing::localizeAndCompare(args, dir_ + "/" + name, dir_ + "/gt.tum", 1.5);
        EXPECT_EQ(r.frames.size(), kCount);
        return r;
    }

    static std::string dir_;
};
std::string CampusTurns::dir_;
}  // namespace

TEST_F(CampusTurns, YawHypothesesKeepEveryFrameOnGroundTruth) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const auto r = localize("recovery", {});
    EXPECT_EQ(r.summary.diverged, 0u);
    EXPECT_GE(r.summary.recovered, 3u);
    EXPECT_LT(r.worst_m, 0.05);
    EXPECT_LT(r.worst_deg, 1.0);
    std::cout << "campus turns with recovery: " << r.summary.recovered << " frames recovered, worst "
              << r.worst_m << " m, " << r.worst_deg << " deg\n";
}

TEST_F(CampusTurns, WithoutRecoveryTheTurnLosesTrack) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const auto r = localize("no_recovery", {"localization.recovery_max_yaw_deg=0"});
    EXPECT_EQ(r.summary.recovered, 0u);
    EXPECT_GT(r.summary.diverged, 0u);
    EXPECT_GT(r.worst_m, 0.3);
    std::cout << "campus turns without recovery: " << r.summary.diverged << " frames diverged, worst "
              << r.worst_m << " m, " << r.worst_deg << " deg\n";
}
