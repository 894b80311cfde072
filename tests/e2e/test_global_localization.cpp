// Localization without an initial pose (doc/health.md, issue 11): each scan of a real split is
// localized on its own by Localizer::relocalize() (the global search, verified by the fine
// registration), in a map built from the other scans (real_split.h), and kidnaps are detected
// and recovered from. A scan may be reported ambiguous or failed; it must never be placed
// confidently wrong: no accepted pose farther than 0.5 m / 5 deg from the ground truth.
// Measured (default INI, deskew off): campus-ouster 53 of 53 within 0.3 m / 3 deg (worst
// 5 cm); kitti00-mini 14 of 16, one accepted 0.40 m along the road (the registration's shallow
// basin there, the basin issue), one reported ambiguous; up to ~3.7 s per KITTI scan on a
// loaded machine.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/se3.h>
#include <superloc/localization/localizer.h>

#include <fstream>
#include <optional>
#include <filesystem>
#include <cstdlib>
#include <sstream>

#include "default_params.h"
#include "real_split.h"

using namespace superloc;
using namespace superloc::localization;

namespace {

using superloc::testing::defaultParams;

struct Tally {
    int accepted_right = 0;  ///< within 0.3 m / 3 deg
    int accepted_near = 0;   ///< within 0.5 m / 5 deg but not 0.3 m / 3 deg
    int accepted_wrong = 0;  ///< farther: confidently wrong
    int ambiguous = 0, failed = 0;
    double worst_m = 0, worst_deg = 0;  ///< over the accepted ones
    double max_ms = 0;
    int total() const { return accepted_right + accepted_near + accepted_wrong + ambiguous + failed; }
};

/// Every scan of `scans` of the split, each in a fresh Localizer with no pose.
Tally eachScanOnItsOwn(const std::string& name, const std::string& data, const std::string& map_scans,
                       const std::string& query_scans, double voxel) {
    Tally t;
    const auto s = superloc::testing::prepareRealSplit(name, data, map_scans, voxel);
    if (!s.ok) return t;
    std::vector<Scan> scans;
    std::vector<SE3d> T_gt;
    superloc::testing::readScans(s.rawlog, query_scans, io::loadTum(s.gt_tum), scans, T_gt, 2.5);
    const LocalizerParams params = defaultParams({"features.deskew=false"});
    auto map = std::make_shared<const map::PriorMap>(map::PriorMap::load(s.map, map::MapParams{}));
    for (size_t i = 0; i < scans.size(); ++i) {
        Localizer loc(params, map);
        loc.setMinLoggingLevel(mrpt::system::LVL_ERROR);
        loc.relocalize();
        const FrameReport r = loc.process(scans[i]);
        t.max_ms = std::max(t.max_ms, r.ms.total);
        if (r.reloc.outcome == RelocOutcome::Accepted) {
            const double dm = translationDistance(r.T_map_lidar, T_gt[i]);
            const double dd = rotationAngle(r.T_map_lidar, T_gt[i]) * 180 / M_PI;
            const bool right = dm <= 0.3 && dd <= 3.0, near = dm <= 0.5 && dd <= 5.0;
            (right ? t.accepted_right : near ? t.accepted_near : t.accepted_wrong)++;
            t.worst_m = std::max(t.worst_m, dm);
            t.worst_deg = std::max(t.worst_deg, dd);
            EXPECT_NE(r.health, Health::Lost) << name << " scan " << i;
            if (!near) ADD_FAILURE() << name << " scan " << i << ": accepted " << dm << " m / " << dd << " deg off";
        } else {
            EXPECT_EQ(r.health, Health::Lost) << name << " scan " << i << ": not placed yet not lost";
            (r.reloc.outcome == RelocOutcome::Ambiguous ? t.ambiguous : t.failed)++;
        }
    }
    std::cout << name << ": " << t.accepted_right << " of " << t.total() << " placed within 0.3 m / 3 deg (worst "
              << t.worst_m << " m, " << t.worst_deg << " deg), " << t.accepted_near << " within 0.5 m / 5 deg, "
              << t.accepted_wrong << " farther, "
              << t.ambiguous << " ambiguous, " << t.failed << " failed; slowest " << t.max_ms << " ms\n";
    return t;
}

}  // namespace

TEST(GlobalLocalization, CampusEveryScanOnItsOwnBothWays) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const Tally a = eachScanOnItsOwn("gloc_campus_even", "campus-ouster", "even", "odd", 0.1);
    const Tally b = eachScanOnItsOwn("gloc_campus_odd", "campus-ouster", "odd", "even", 0.1);
    EXPECT_EQ(a.total() + b.total(), 53);
    EXPECT_EQ(a.accepted_wrong + b.accepted_wrong, 0);
    EXPECT_GE(a.accepted_right + b.accepted_right, 51) << "95 % of 53";
}

TEST(GlobalLocalization, KittiEveryScanOnItsOwnBothWays) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini/gt_velodyne_tum.txt");
    const Tally a = eachScanOnItsOwn("gloc_kitti_even", "kitti00-mini", "even", "odd", 0.2);
    const Tally b = eachScanOnItsOwn("gloc_kitti_odd", "kitti00-mini", "odd", "even", 0.2);
    EXPECT_EQ(a.total() + b.total(), 16);
    EXPECT_EQ(a.accepted_wrong + b.accepted_wrong, 0);
    EXPECT_GE(a.accepted_right + b.accepted_right, 14) << "14-15 of 16 measured";
}

// A kidnap on real data: campus-ouster's odd scans 0-9, then (2 s later, as if the next scan)
// odd scans 18-25: the walker is carried 11.9 m and turned 103 deg between two scans. The map
// holds the even scans only. The kidnap must be detected (a lost frame) within 3 frames, the
// pose found again within 10, and no frame in between reported ok while more than 0.5 m off.
TEST(GlobalLocalization, CampusKidnapDetectedAndRecovered) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const auto s = superloc::testing::prepareRealSplit("gloc_kidnap_campus", "campus-ouster", "even", 0.1);
    ASSERT_TRUE(s.ok);
    std::vector<Scan> odd;
    std::vector<SE3d> T_odd;
    superloc::testing::readScans(s.rawlog, "odd", io::loadTum(s.gt_tum), odd, T_odd, 2.5);
    ASSERT_EQ(odd.size(), 26u);
    std::vector<Scan> scans;
    std::vector<SE3d> T_gt;
    for (size_t i = 0; i < 10; ++i) scans.push_back(odd[i]), T_gt.push_back(T_odd[i]);
    const double shift = odd[9].t + 2.0 - odd[18].t;
    for (size_t i = 18; i < 26; ++i) {
        scans.push_back(odd[i]);
        scans.back().t += shift;
        T_gt.push_back(T_odd[i]);
    }
    const size_t k = 10;  // the first frame after the kidnap
    ASSERT_GT(translationDistance(T_gt[k - 1], T_gt[k]), 5.0);
    ASSERT_GT(rotationAngle(T_gt[k - 1], T_gt[k]), M_PI / 2);

    auto map = std::make_shared<const map::PriorMap>(map::PriorMap::load(s.map, map::MapParams{}));
    Localizer loc(defaultParams({"features.deskew=false"}), map);
    loc.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    loc.setInitialPose(T_gt[0]);
    std::optional<size_t> detected, recovered;
    for (size_t i = 0; i < scans.size(); ++i) {
        const FrameReport r = loc.process(scans[i]);
        const double dm = translationDistance(r.T_map_lidar, T_gt[i]);
        const double dd = rotationAngle(r.T_map_lidar, T_gt[i]) * 180 / M_PI;
        std::cout << "frame " << i << ": " << healthName(r.health) << " (" << r.health_reason << ") " << r.reloc.mode
                  << " " << r.reloc.trigger << " " << relocOutcomeName(r.reloc.outcome) << ", " << dm << " m / " << dd << " deg off, " << r.ms.total << " ms\n";
        if (r.health == Health::Ok) {
            EXPECT_TRUE(dm <= 0.5 && dd <= 5.0) << "frame " << i << " confidently wrong";
        }
        if (i < k) {
            EXPECT_LT(dm, 0.1) << "frame " << i << " before the kidnap";
        }
        // Detected: the frame was lost (and then relocalized, or not).
        if (i >= k && !detected && (r.health == Health::Lost || r.reloc.trigger == "lost")) detected = i;
        if (i >= k && !recovered && r.reloc.outcome == RelocOutcome::Accepted && dm < 0.3 && dd < 3.0) recovered = i;
        if (recovered && i > *recovered) {
            EXPECT_LT(dm, 0.3) << "frame " << i << " after the relocalization";
        }
    }
    ASSERT_TRUE(detected.has_value()) << "the kidnap was never detected";
    EXPECT_LE(*detected, k + 2);
    ASSERT_TRUE(recovered.has_value()) << "never relocalized";
    EXPECT_LE(*recovered, k + 9);
    std::cout << "campus kidnap (11.9 m, 103 deg): detected at frame " << *detected - k << ", relocalized at frame "
              << *recovered - k << " after it\n";
}

// The paper's point, for relocalization: inside a 150 m corridor with nothing along its axis a
// scan fits anywhere along x, so no pose may be committed: every scan from inside is reported
// ambiguous (verified alternatives along the corridor, or x weakly constrained), never placed.
TEST(GlobalLocalization, FeaturelessCorridorIsAmbiguousNotPlaced) {
    namespace fs = std::filesystem;
    const std::string dir = superloc::testing::freshDir("gloc_corridor");
    const std::string sim = std::string(SUPERLOC_BINARY_DIR) + "/bin/superloc-sim";
    if (!fs::exists(sim)) GTEST_SKIP() << "superloc-sim not built";
    const std::string cmd = sim + " " + superloc::testing::sourcePath("ini/sim/corridor.ini") + " --out " + dir +
                            " --set corridor.length=150 --set corridor.recesses=0 --set sim.duration=12"
                            " --set lidar.preset=../sensors/vlp16.ini > " + dir + "/sim.log 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const Trajectory gt = io::loadTum(dir + "/gt_tum.txt");
    io::RawlogReader reader(dir + "/sequence.rawlog", io::RawlogParams{});
    io::RawlogItem it;
    std::vector<Scan> scans;
    std::vector<SE3d> T_gt;
    int n = 0;
    while (reader.next(it))
        if (it.kind == io::RawlogItem::Kind::Lidar && it.scan().t - gt.front().t > 3.0 && n++ % 15 == 0) {
            const auto g = interpolateAt(gt, it.scan().t, 0.5, 1e-3);
            if (g) scans.push_back(it.scan()), T_gt.push_back(*g);
        }
    ASSERT_GE(scans.size(), 5u);
    auto map = std::make_shared<const map::PriorMap>(map::PriorMap::load(dir + "/prior_map.pcd", map::MapParams{}));
    int ambiguous = 0;
    for (size_t i = 0; i < scans.size(); ++i) {
        Localizer loc(defaultParams({}), map);
        loc.setMinLoggingLevel(mrpt::system::LVL_ERROR);
        loc.relocalize();
        const FrameReport r = loc.process(scans[i]);
        std::cout << "corridor scan at x = " << T_gt[i].translation().x() << ": " << relocOutcomeName(r.reloc.outcome) << " ("
                  << r.reloc.detail << "), " << r.reloc.hypotheses << " hypotheses, " << r.reloc.verified
                  << " verified, " << r.ms.total << " ms\n";
        EXPECT_NE(r.reloc.outcome, RelocOutcome::Accepted) << "scan " << i;
        EXPECT_EQ(r.health, Health::Lost) << "scan " << i;
        ambiguous += r.reloc.outcome == RelocOutcome::Ambiguous;
    }
    EXPECT_GE(ambiguous, static_cast<int>(scans.size()) - 1) << "reported ambiguous (not just failed)";
}
