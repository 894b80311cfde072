// Fault suite on real sequences (no IMU, no odom_alt), by the honest protocol only: the prior
// map is built from the even scans (real_split.h), the odd scans alone are rewritten with the
// fault and localized in it, with the settings of test_localize_real.cpp (deskew off: both sets
// come motion-compensated; voxel association; 10 rounds) from the GT pose of the first odd scan.
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/io/rawlog.h>
#include <superloc_testing/testing.h>
#include <sys/file.h>
#include <unistd.h>

#include <cmath>
#include <iomanip>
#include <fcntl.h>
#include <filesystem>

#include "faults.h"
#include "real_split.h"

using namespace superloc;
using superloc::testing::FaultRun;
using superloc::testing::rewriteRawlog;
using superloc::testing::runLocalize;
using superloc::testing::writeItem;
namespace fs = std::filesystem;

namespace {

using Edit = std::function<void(io::RawlogItem&, io::RawlogWriter&)>;
const Edit keepAll = [](io::RawlogItem& it, io::RawlogWriter& w) { writeItem(w, it); };

class FaultsReal : public ::testing::Test {
 protected:
    /// The split of `data` (import + map from the even scans), made once per build of this test
    /// executable and shared by its processes under a file lock (CTest runs each case in its own
    /// process). False when the shared data is missing.
    bool prepare(const std::string& data, double voxel) {
        if (!fs::exists(superloc::testing::sharedData(data))) return false;
        const fs::path dir = fs::path(SUPERLOC_BINARY_DIR) / "test-output" / ("faults_real_" + data);
        fs::create_directories(dir);
        const int lock = ::open((dir / "lock").c_str(), O_CREAT | O_RDWR, 0644);
        EXPECT_GE(lock, 0);
        ::flock(lock, LOCK_EX);
        const fs::path done = dir / "done";
        const fs::path self = fs::read_symlink("/proc/self/exe");
        split_.gt_tum = superloc::testing::sharedData(data + (data == "kitti00-mini" ? "/gt_velodyne_tum.txt"
                                                                                    : "/gt_tum.txt"));
        split_.rawlog = (dir / "all.rawlog").string();
        split_.map = (dir / "map_even.pcd").string();
        if (!fs::exists(done) || fs::last_write_time(done) < fs::last_write_time(self)) {
            const auto s = superloc::testing::prepareRealSplit("faults_real_prep_" + data, data, "even", voxel);
            fs::copy_file(s.rawlog, split_.rawlog, fs::copy_options::overwrite_existing);
            fs::copy_file(s.map, split_.map, fs::copy_options::overwrite_existing);
            fs::remove_all(s.dir);
            std::ofstream(done) << "ok\n";
        }
        ::flock(lock, LOCK_UN);
        ::close(lock);
        dir_ = superloc::testing::freshDir("faults_real_" + data);
        return true;
    }
    /// The odd scans rewritten by `edit` into DIR/NAME.rawlog, localized into DIR/NAME.
    FaultRun run(const std::string& name, const Edit& edit) {
        const std::string rawlog = dir_ + "/" + name + ".rawlog";
        rewriteRawlog(split_.rawlog, rawlog, "odd", edit);
        return runLocalize({"--rawlog", rawlog, "--map", split_.map, "--initial-pose-tum", split_.gt_tum, "--set",
                            "features.deskew=false", "--set", "association.kind=voxel", "--set",
                            "localization.rounds=10", "--method", "superloc"},
                           dir_ + "/" + name, split_.gt_tum);
    }
    /// Times of the odd scans.
    std::vector<double> oddTimes() const {
        std::vector<double> t;
        const Trajectory gt = io::loadTum(split_.gt_tum);
        for (size_t i = 1; i < gt.size(); i += 2) t.push_back(gt[i].t);
        return t;
    }
    superloc::testing::RealSplit split_;
    std::string dir_;
};

void report(const std::string& what, const FaultRun& r) {
    std::cout << what << ": exit " << r.exit_code << ", " << r.trajectory.size() << " frames, error [m]:";
    for (double e : r.err_m) std::cout << " " << std::setprecision(3) << e;
    std::cout << "\n";
}

bool at(double t, double t_ref) { return std::abs(t - t_ref) < 0.01; }

}  // namespace

// (1) campus-ouster, odd scans (2 s apart, a walk turning up to ~90 deg between them): one scan
// dropped, so 4 s pass between two frames. Without IMU the prediction is constant velocity over
// the gap; the frame after it is tracked as in the clean run (measured 1.8 cm, the same as
// without the fault; the clean run's worst frame is 3.9 cm).
TEST_F(FaultsReal, CampusLidarDropout) {
    if (!prepare("campus-ouster", 0.1)) GTEST_SKIP() << "no campus-ouster";
    const auto t = oddTimes();
    const FaultRun r = run("dropout", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        if (it.kind == io::RawlogItem::Kind::Lidar && at(it.time(), t.at(12))) return;
        writeItem(w, it);
    });
    report("campus dropout", r);
    EXPECT_EQ(r.exit_code, 0);
    ASSERT_EQ(r.trajectory.size(), t.size() - 1);
    EXPECT_TRUE(at(r.trajectory.at(12).t, t.at(13)));
    EXPECT_LT(r.err_m.at(12), 0.05) << "the frame after the gap";
    EXPECT_LT(superloc::testing::maxWhere(r, [](double) { return true; }), 0.05);
    EXPECT_EQ(r.summary.at("frames_diverged"), 0);
}

// (6) campus-ouster: a scan cut to 5 points. Fewer than the 10 correspondences a solve needs
// and no IMU: the frame keeps its constant-velocity prediction and is reported diverged
// ("no_correspondences"); the next frame is tracked again (measured 1.8 cm, as in the clean run).
TEST_F(FaultsReal, CampusFivePointScan) {
    if (!prepare("campus-ouster", 0.1)) GTEST_SKIP() << "no campus-ouster";
    const auto t = oddTimes();
    const FaultRun r = run("five", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        if (it.kind == io::RawlogItem::Kind::Lidar && at(it.time(), t.at(12))) {
            auto& s = std::get<Scan>(it.data);
            std::vector<Vec3f> p;
            for (size_t k = 0; k < 5; ++k) p.push_back(s.points[k * (s.points.size() / 5)]);
            s.points = p;
            s.intensity.clear();
        }
        writeItem(w, it);
    });
    report("campus five points", r);
    EXPECT_EQ(r.exit_code, 0);
    ASSERT_EQ(r.trajectory.size(), t.size());
    EXPECT_EQ(r.frames.num(12, "points_raw"), 5);
    EXPECT_EQ(r.frames.num(12, "diverged"), 1);
    EXPECT_EQ(r.frames.text(12, "diverged_reason"), "no_correspondences");
    EXPECT_EQ(r.summary.at("frames_diverged"), 1);
    EXPECT_LT(superloc::testing::maxWhere(r, [&](double tt) { return tt > t.at(12) + 0.01; }), 0.05)
        << "every frame after the fault";
}

// (5) kitti00-mini, odd scans (0.2 s apart, ~1.7 m): one scan all NaN/-inf, a later one 95 %.
// The first is skipped by the reader (no frame; rawlog.scans_empty_skipped = 1), so the next
// frame is predicted over 0.4 s (measured 0.43 m off; the clean run's frames are 0.04-0.38 m
// off: this split is the hard one); the 95 % one is localized from its ~6000 points and the
// frames from there on are back to the clean run's (0.027, 0.054, 0.083 m vs 0.038, 0.071,
// 0.076 m).
TEST_F(FaultsReal, KittiNanFloodedScan) {
    if (!prepare("kitti00-mini", 0.2)) GTEST_SKIP() << "no kitti00-mini";
    const auto t = oddTimes();
    const FaultRun r = run("nan", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        if (it.kind == io::RawlogItem::Kind::Lidar && (at(it.time(), t.at(3)) || at(it.time(), t.at(5)))) {
            auto& s = std::get<Scan>(it.data);
            const bool all = at(it.time(), t.at(3));
            for (size_t i = 0; i < s.points.size(); ++i)
                if (all || i % 20 != 0) s.points[i].setConstant(i % 3 ? NAN : -INFINITY);
        }
        writeItem(w, it);
    });
    report("kitti nan", r);
    EXPECT_EQ(r.exit_code, 0);
    ASSERT_EQ(r.trajectory.size(), t.size() - 1);
    EXPECT_TRUE(at(r.trajectory.at(3).t, t.at(4))) << "the all-NaN scan makes no frame";
    EXPECT_LT(r.frames.num(4, "points_raw"), 0.06 * 124000);
    EXPECT_EQ(r.summary.at("rawlog").at("scans_empty_skipped"), 1);
    EXPECT_EQ(r.summary.at("frames_diverged"), 0);
    EXPECT_LT(r.err_m.at(3), 0.6) << "predicted over 0.4 s";
    // 0.027-0.123 m measured (kd-tree association on this split; the clean run 0.038-0.076 m).
    for (size_t i = 4; i < r.err_m.size(); ++i) EXPECT_LT(r.err_m[i], 0.15) << "frame " << i;
}

// (4) kitti00-mini: a scan stamped 1 s early (beyond the 0.5 s reorder window): exit 1 with one
// line naming the file, the entry and the jump; every scan read before it is localized and
// written (the reader empties its re-sort window first), summary.json says "failed".
TEST_F(FaultsReal, KittiBackwardsTimestamp) {
    if (!prepare("kitti00-mini", 0.2)) GTEST_SKIP() << "no kitti00-mini";
    const auto t = oddTimes();
    double t_newest = 0;  // of the items written before the bad one
    bool done = false;
    const FaultRun r = run("backwards", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        if (it.kind == io::RawlogItem::Kind::Lidar && at(it.time(), t.at(5))) {
            std::get<Scan>(it.data).t -= 1.0;
            done = true;
        }
        if (!done) t_newest = std::max(t_newest, it.time());
        writeItem(w, it);
    });
    report("kitti backwards", r);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.stderr_text.find("timestamp goes backwards"), std::string::npos) << r.stderr_text;
    // Every odd scan written before the bad one (the reader returns its 0.5 s window before the
    // error; it used to drop it and keep 3).
    size_t expected = 0;
    while (t.at(expected) <= t_newest) ++expected;
    EXPECT_EQ(expected, 5u);
    ASSERT_EQ(r.trajectory.size(), expected);
    for (size_t i = 0; i < expected; ++i) EXPECT_TRUE(at(r.trajectory[i].t, t[i]));
    EXPECT_EQ(r.summary.at("status"), "failed");
    EXPECT_TRUE(fs::exists(r.dir + "/localized_map.pcd"));
}
