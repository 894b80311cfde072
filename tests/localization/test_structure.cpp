// The Localizer's parts (doc/localizer.md "Structure") on the synthetic box room (box_room.h):
// a verification leaves the frame and the next frames as they were (no state to save and
// restore), the outputs come with the frame that asked for them, the initial pose is resolved in
// StartPose, and the HealthMonitor alone turns the others' evidence into a health.
#include <gtest/gtest.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/localization/localizer.h>
#include <superloc/localization/start_pose.h>
#include <superloc/localization/tracker.h>

#include <filesystem>
#include <fstream>
#include <cctype>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "box_room.h"

using namespace superloc;
using namespace superloc::localization;
using namespace superloc::testing;

namespace {

const SE3d kImuLidar = [] {
    SE3d T = SE3d::Identity();
    T.translation() = Vec3d(0.05, 0, 0.1);
    return T;
}();

std::shared_ptr<const map::PriorMap> boxMap() {
    map::MapParams mp;
    mp.voxel_size = 0.1;
    return std::make_shared<map::PriorMap>(boxSurface(0.05), mp, Vec3f(0, 0, 1.5));
}

LocalizerParams boxParams() {
    LocalizerParams p;
    p.features.voxel_size = 0.3;
    return p;
}

/// Distance of a map-frame point to the nearest wall of the box room.
double toWall(const Vec3f& p) {
    double d = 1e9;
    for (int k = 0; k < 3; ++k) d = std::min({d, std::abs(p[k] - kRoomMin[k]), std::abs(p[k] - kRoomMax[k])});
    return d;
}

}  // namespace

// The Tracker alone, twice over 12 frames (with IMU, and without: constant velocity and the
// motion measured against the last scan): one of them also verifies three poses 0.3-1 m off on
// every frame between its own solve and its end, as the Recovery does. Every report and state
// must be the same to the bit: a verification returns its own FrameSolution and changes neither
// the frame's nor what the next frames start from.
TEST(Tracker, VerifyingPosesChangesNothingOfTheFrame) {
    const Motion m;
    const auto map = boxMap();
    mrpt::system::COutputLogger log("test");
    log.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    for (const bool use_imu : {true, false}) {
        LocalizerParams p = boxParams();
        p.loc.use_imu = use_imu;
        const MethodVariant variant = makeMethodVariant(Method::Icp, p.fusion, p.risk);
        SensorHistory sensors[2];
        std::vector<std::unique_ptr<Tracker>> trackers;
        for (int k = 0; k < 2; ++k) {
            trackers.push_back(std::make_unique<Tracker>(p, variant, sensors[k], log));
            trackers[k]->setMap(map, nullptr);
        }
        double t_imu[2] = {0, 0};
        int verified = 0;
        for (int i = 1; i <= 12; ++i) {
            const double t = 0.1 * i;
            const Scan scan = sweep(m, kImuLidar, t);
            FrameReport rep[2];
            FrameSolution sol[2];
            for (int k = 0; k < 2; ++k) {
                for (const ImuSample& smp : imuUpTo(m, t, t_imu[k])) sensors[k].addImu(smp);
                Tracker& tr = *trackers[k];
                Frame f;
                tr.begin(scan, m.T(0.1) * kImuLidar, f);
                const bool unknown = tr.velocityUnknown(f, true);
                sol[k] = tr.track(f, unknown);
                rep[k] = FrameReport(static_cast<size_t>(i), t, sol[k].report);
                if (k == 1) {
                    for (const double dx : {0.3, -0.6, 1.0}) {
                        fusion::FrameState start = sol[k].state;
                        start.setPose(SE3d(Eigen::Translation3d(dx, 0.5 * dx, 0)) * start.T_map_imu());
                        const FrameSolution v = tr.solveFrom(f, start, VerifyAs::Hypothesis, rep[k].track());
                        verified += v.report.rounds > 0 && !v.corr.empty();
                    }
                }
                tr.end(f, sol[k].state, sol[k], rep[k], false, false, false);
            }
            const std::string at = (use_imu ? "IMU, frame " : "no IMU, frame ") + std::to_string(i);
            EXPECT_EQ(rep[0].T_map_lidar.matrix(), rep[1].T_map_lidar.matrix()) << at;
            EXPECT_EQ(rep[0].T_map_lidar_pred.matrix(), rep[1].T_map_lidar_pred.matrix()) << at;
            EXPECT_EQ(rep[0].velocity, rep[1].velocity) << at;
            EXPECT_EQ(rep[0].inlier_ratio, rep[1].inlier_ratio) << at;
            EXPECT_EQ(rep[0].iterations, rep[1].iterations) << at;
            EXPECT_EQ(rep[0].est_sigma, rep[1].est_sigma) << at;
            EXPECT_EQ(rep[0].motion_from_scan, rep[1].motion_from_scan) << at;
            EXPECT_EQ(sol[0].corr.size(), sol[1].corr.size()) << at;
            EXPECT_LT(translationDistance(rep[0].T_map_lidar, m.T(t) * kImuLidar), use_imu ? 0.02 : 0.1) << at;
            if (!use_imu && i == 2) {
                EXPECT_TRUE(rep[0].motion_from_scan) << "the second frame measures its motion";
            }
        }
        EXPECT_EQ(verified, 36);  // every verification solved something
    }
}

// A start seed (VerifyAs::Seed) is solved as a search's hypothesis is, from the same pose, and
// only measured differently: on its solve's own voxel-map correspondences instead of a fresh
// association of every feature (doc/health.md "Start"). With [relocalization]
// hypothesis_features it is solved and measured on every k-th feature, while a hypothesis is
// polished and measured on them all.
TEST(Tracker, ASeedIsSolvedAsAHypothesisAndMeasuredOnItsOwnFeatures) {
    const Motion m;
    // The room moved off the voxel grid: its walls on the voxel faces (x = -6, 6 ...) leave the
    // voxel association of a search nothing to hold a wall with (a feature at 5.98 m falls in a
    // voxel without the wall's points).
    const Vec3d shift(0.23, 0.17, 0.11);
    PointCloud room = boxSurface(0.05);
    for (Vec3f& q : room.points) q += shift.cast<float>();
    map::MapParams mp;
    mp.voxel_size = 0.1;
    const auto map = std::make_shared<map::PriorMap>(room, mp, Vec3f(0, 0, 1.5) + shift.cast<float>());
    const SE3d T_shift(Eigen::Translation3d(shift.x(), shift.y(), shift.z()));
    mrpt::system::COutputLogger log("test");
    log.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    for (const int subset : {0, 100}) {
        LocalizerParams p = boxParams();
        p.relocalization.hypothesis_features = subset;
        const MethodVariant variant = makeMethodVariant(Method::Icp, p.fusion, p.risk);
        SensorHistory sensors;
        Tracker tr(p, variant, sensors, log);
        tr.setMap(map, nullptr);
        double t_imu = 0;
        for (int i = 1; i <= 6; ++i) {
            const double t = 0.1 * i;
            for (const ImuSample& smp : imuUpTo(m, t, t_imu)) sensors.addImu(smp);
            const Scan scan = sweep(m, kImuLidar, t);
            Frame f;
            tr.begin(scan, T_shift * m.T(0.1) * kImuLidar, f);
            FrameSolution own = tr.track(f, tr.velocityUnknown(f, true));
            FrameReport rep(static_cast<size_t>(i), t, own.report);
            const std::string at = "hypothesis_features " + std::to_string(subset) + ", frame " + std::to_string(i);
            ASSERT_LT(translationDistance(own.report.T_map_lidar, T_shift * m.T(t) * kImuLidar), 0.03) << at;
            if (i == 6) {
                const size_t n = f.features.pts_body.size();
                ASSERT_GT(n, 150u) << "the room's scan must have more features than the subset";
                fusion::FrameState start = own.state;
                start.setPose(SE3d(Eigen::Translation3d(0.3, -0.2, 0)) * start.T_map_imu());
                const FrameSolution seed = tr.solveFrom(f, start, VerifyAs::Seed, rep.track());
                const FrameSolution hyp = tr.solveFrom(f, start, VerifyAs::Hypothesis, rep.track());
                ASSERT_FALSE(seed.report.diverged) << at;
                ASSERT_FALSE(hyp.report.diverged) << at;
                // Both settle where the frame's own solve did (the room holds every axis); a
                // seed on 100 features at the voxel map's 0.5 m level within a tenth of a metre
                // (3.3 cm measured), a third of what tells two start basins apart
                // (start_distinct_xyz, 0.3 m).
                EXPECT_LT(translationDistance(seed.report.T_map_lidar, own.report.T_map_lidar), subset ? 0.1 : 0.03)
                    << at;
                EXPECT_LT(translationDistance(hyp.report.T_map_lidar, own.report.T_map_lidar), 0.03) << at;
                EXPECT_GT(seed.report.inlier_ratio, 0.8) << at;
                EXPECT_GT(hyp.report.inlier_ratio, 0.8) << at;
                if (subset == 0) {
                    // The same solve: the same pose to the last bit; measured on every feature both.
                    EXPECT_EQ(seed.report.T_map_lidar.matrix(), hyp.report.T_map_lidar.matrix());
                    EXPECT_GT(seed.corr.size(), n / 2);
                } else {
                    // The seed's fit is that of its subset; the hypothesis's of every feature.
                    EXPECT_LE(seed.corr.size(), static_cast<size_t>(subset));
                    EXPECT_GT(hyp.corr.size(), static_cast<size_t>(subset));
                }
            }
            tr.end(f, own.state, own, rep, false, false, false);
        }
    }
}

// process(scan, &outputs): the localized-map and observability points of the frame that asked,
// on the walls of the room (deskewed, at the solved pose), and asking for them changes nothing
// of the localization.
TEST(Localizer, OutputsComeWithTheFrameThatAskedForThem) {
    const Motion m;
    const auto map = boxMap();
    Localizer with(boxParams(), map), without(boxParams(), map);
    for (Localizer* l : {&with, &without}) {
        l->setMinLoggingLevel(mrpt::system::LVL_ERROR);
        l->setInitialPose(m.T(0.1) * kImuLidar);
    }
    double t_imu = 0;
    FrameOutputs out;
    out.map_voxel = 0.2;
    out.observability = true;
    for (int i = 1; i <= 8; ++i) {
        const double t = 0.1 * i;
        for (const ImuSample& smp : imuUpTo(m, t, t_imu)) with.addImu(smp), without.addImu(smp);
        const Scan scan = sweep(m, kImuLidar, t);
        const FrameReport a = with.process(scan, &out);
        const FrameReport b = without.process(scan);
        EXPECT_EQ(a.T_map_lidar.matrix(), b.T_map_lidar.matrix()) << "frame " << i;
        EXPECT_EQ(a.health, b.health);
        ASSERT_GT(out.map_points.size(), 100u) << "frame " << i;
        double worst = 0;
        for (const Vec3f& q : out.map_points) worst = std::max(worst, toWall(q));
        EXPECT_LT(worst, 0.03) << "frame " << i << ": a map point off the walls";
        ASSERT_EQ(out.obs_points.size(), out.obs_labels.size());
        // the final association's kept correspondences (a weight-0 one is counted, not kept)
        EXPECT_GT(out.obs_points.size(), 100u) << "frame " << i;
        EXPECT_LE(out.obs_points.size(), a.corr_plane + a.corr_line + a.corr_point) << "frame " << i;
        for (const Vec3f& q : out.obs_points) EXPECT_LT(toWall(q), 0.03);
        for (const int8_t l : out.obs_labels) EXPECT_TRUE(l == risk::kNoLabel || (l >= 0 && l <= 2));
    }
}

// The one place an initial pose is resolved: within the map's bounds it is taken; outside, an
// error naming it, or the global search with out_of_map = global (when there is a search); a
// TUM trajectory gives its pose at the first scan's time; the start check's seeds cover the
// given pose's uncertainty.
TEST(StartPose, InitialPoseResolvedInOnePlace) {
    const auto map = boxMap();  // x -6..6, y -4..4, z 0..3
    RelocalizationParams rp;
    StartPose s(rp, 10.0);
    EXPECT_EQ(s.give(makePoseRPY(15, 0, 1, 0, 0, 0), "--initial-pose", *map, true), StartPose::Decision::Take);
    ASSERT_TRUE(s.given().has_value());
    EXPECT_NEAR(s.firstPose().translation().x(), 15, 1e-12);
    try {
        s.give(makePoseRPY(17, 0, 1, 0, 0, 0), "--initial-pose", *map, true);
        ADD_FAILURE() << "no error 1 m beyond the map's bounds + max_range";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("--initial-pose"), std::string::npos) << msg;
        EXPECT_NE(msg.find("outside the prior map"), std::string::npos) << msg;
        EXPECT_NE(msg.find("out_of_map"), std::string::npos) << msg;
    }
    SE3d nan = SE3d::Identity();
    nan.translation().x() = std::nan("");
    EXPECT_THROW(s.give(nan, "pose", *map, true), ConfigError);
    rp.out_of_map = "global";
    EXPECT_EQ(s.give(makePoseRPY(1e300, 0, 0, 0, 0, 0), "p", *map, true), StartPose::Decision::Search);
    EXPECT_FALSE(s.given().has_value());
    EXPECT_THROW(s.give(makePoseRPY(1e300, 0, 0, 0, 0, 0), "p", *map, false), ConfigError);

    Trajectory traj = {{10.0, makePoseRPY(0, 0, 1, 0, 0, 0), {}}, {11.0, makePoseRPY(2, 0, 1, 0, 0, 0), {}}};
    bool covered = false;
    s.giveTrajectory(traj, "gt.txt");
    ASSERT_EQ(s.atFirstScan(10.25, *map, true, covered), StartPose::Decision::Take);
    EXPECT_TRUE(covered);
    EXPECT_NEAR(s.firstPose().translation().x(), 0.5, 1e-9);
    EXPECT_FALSE(s.atFirstScan(10.25, *map, true, covered).has_value()) << "resolved once";
    s.giveTrajectory(traj, "gt.txt");
    ASSERT_EQ(s.atFirstScan(50.0, *map, true, covered), StartPose::Decision::Take);
    EXPECT_FALSE(covered);
    EXPECT_NEAR(s.firstPose().translation().x(), 0.0, 1e-12) << "not covered: its first pose";
    EXPECT_THROW(s.giveTrajectory({}, "empty.txt"), ConfigError);

    // Seeds: the given yaw turned either way, and a ring of six at 2/3 start_xyz at three yaws.
    const SE3d T0 = makePoseRPY(1, 2, 1, 0, 0, 0.4);
    const auto seeds = StartPose::seeds(T0, rp);
    EXPECT_EQ(seeds.size(), 20u);
    for (const SE3d& T : seeds) {
        EXPECT_LE(translationDistance(T, T0), rp.start_xyz * 2 / 3 + 1e-9);
        EXPECT_LE(rotationAngle(T, T0), rp.start_deg * 2 / 3 * kDeg + 1e-9);
        EXPECT_GT(translationDistance(T, T0) + rotationAngle(T, T0), 0.01) << "a seed is the given pose";
    }
    rp.start_ring_yaws = 1;
    EXPECT_EQ(StartPose::seeds(T0, rp).size(), 8u);
    rp.start_xyz = rp.start_deg = 0;
    EXPECT_TRUE(StartPose::seeds(T0, rp).empty());
}

// The frame's state has one writer (doc/localizer.md "Structure"), read off the sources of
// modules/localization: no function but Localizer::process (localizer.cpp) takes a writable
// FrameReport; the Recovery and its helpers hold no Tracker and no HealthMonitor; a health is
// assigned only from a Verdict (FrameReport::setVerdict) made by the health checks (health.cpp).
TEST(Structure, OneWriterOfTheFrameReport) {
    namespace fs = std::filesystem;
    const fs::path root = fs::path(SUPERLOC_SOURCE_DIR) / "modules" / "localization";
    const auto read = [](const fs::path& p) {
        std::ifstream in(p);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    };
    size_t files = 0;
    const std::regex writable(R"((^|[^\w])FrameReport\s*&)");
    const std::regex health_set(R"((\.|->|\b)health\s*=[^=])");
    for (const auto& e : fs::recursive_directory_iterator(root)) {
        if (!e.is_regular_file()) continue;
        const std::string name = e.path().filename().string();
        if (e.path().extension() != ".h" && e.path().extension() != ".cpp") continue;
        ++files;
        const std::string text = read(e.path());
        std::istringstream lines(text);
        std::string line;
        int n = 0;
        while (std::getline(lines, line)) {
            ++n;
            const auto code = line.substr(0, line.find("//"));
            for (auto it = std::sregex_iterator(code.begin(), code.end(), writable); it != std::sregex_iterator(); ++it) {
                std::string before = code.substr(0, code.find("FrameReport", static_cast<size_t>(it->position())));
                while (!before.empty() && std::isspace(static_cast<unsigned char>(before.back()))) before.pop_back();
                const bool is_const = before.size() >= 5 && before.compare(before.size() - 5, 5, "const") == 0;
                if (!is_const && name != "localizer.cpp")
                    ADD_FAILURE() << name << ":" << n << ": a writable FrameReport: " << line;
            }
            if (std::regex_search(code, health_set) && name != "health.cpp" && name != "frame_report.h" &&
                code.find("HealthParams") == std::string::npos && code.find("Health health") == std::string::npos)
                ADD_FAILURE() << name << ":" << n << ": a health assigned outside the health checks: " << line;
        }
        if (name == "recovery.h" || name == "verify.h" || name == "candidates.h") {
            for (const char* held : {"HealthMonitor&", "HealthMonitor &", "Tracker&", "Tracker &"})
                EXPECT_EQ(text.find(held), std::string::npos) << name << " holds a " << held;
        }
    }
    EXPECT_GT(files, 40u) << root;
}
