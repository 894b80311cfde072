// Fault suite on a simulated sequence with IMU and odom_alt (issue 14): an 8 s handheld walk in
// the office world (OS1-64, 200 Hz IMU, 20 Hz odom_alt), rewritten with one fault each, localized
// by the superloc-localize executable from the GT start. Every test checks what every run must
// keep (faults.h: outputs agree frame by frame, summary.json parses, stderr/exit code), the
// documented behaviour of the fault (doc/localizer.md "Faults") and that the track is back after
// it. The clean sequence (test FaultsSim.CleanControl) is the yardstick: worst frame 3.3 cm.
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/io/rawlog.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <iomanip>
#include <filesystem>

#include "faults.h"
#include "sim_sequence.h"

using namespace superloc;
using superloc::testing::FaultRun;
using superloc::testing::rewriteRawlog;
using superloc::testing::runLocalize;
using superloc::testing::writeItem;
namespace fs = std::filesystem;

namespace {

constexpr double kDuration = 8.0;  // [s] of simulated walk
constexpr double kFault = 3.0;     // [s] after the first scan: where each fault starts

/// The office sequence, simulated once per build of superloc-sim and shared by the test processes.
std::string officeSequence() {
    return superloc::testing::simulatedSequence("faults_sim_office", "office",
                                                "--set sim.duration=" + std::to_string(kDuration));
}

class FaultsSim : public ::testing::Test {
 protected:
    void SetUp() override {
        seq_ = officeSequence();
        if (seq_.empty()) GTEST_SKIP() << "superloc-sim not built";
        dir_ = superloc::testing::freshDir("faults_sim");
        gt_ = seq_ + "/gt_tum.txt";
        t0_ = io::loadTum(gt_).front().t;
    }
    /// The sequence rewritten by `edit` into DIR/NAME.rawlog, localized into DIR/NAME.
    FaultRun run(const std::string& name, const std::function<void(io::RawlogItem&, io::RawlogWriter&)>& edit,
                 const std::string& method = "superloc") {
        const std::string rawlog = dir_ + "/" + name + ".rawlog";
        rewriteRawlog(seq_ + "/sequence.rawlog", rawlog, "all", edit);
        return runLocalize({"--rawlog", rawlog, "--map", seq_ + "/prior_map.pcd", "--initial-pose-tum", gt_,
                            "--method", method},
                           dir_ + "/" + name, gt_);
    }
    /// Scan times of the clean sequence.
    std::vector<double> scanTimes() const {
        std::vector<double> t;
        for (const auto& p : io::loadTum(gt_)) t.push_back(p.t);
        return t;
    }
    std::string seq_, dir_, gt_;
    double t0_ = 0;
};

const auto keepAll = [](io::RawlogItem& it, io::RawlogWriter& w) { writeItem(w, it); };

/// Measured on the clean sequence (FaultsSim.CleanControl): worst frame 2.7 cm, median 1.2 cm.
/// After a fault every frame must be back within 5 cm of the GT (about twice the clean worst,
/// a quarter of inlier_dist), and from 1 s after the fault's end within 3.5 cm, the clean
/// envelope plus 1 cm (sanitized builds round differently).
constexpr double kRecoveredM = 0.05, kSettledM = 0.035;

void expectRecovered(const FaultRun& r, double t_end) {
    const double first = superloc::testing::maxWhere(r, [&](double t) { return t > t_end; });
    const double settled = superloc::testing::maxWhere(r, [&](double t) { return t > t_end + 1.0; });
    EXPECT_LT(first, kRecoveredM) << "worst frame after the fault";
    EXPECT_LT(settled, kSettledM) << "worst frame from 1 s after the fault";
    std::cout << "  after the fault: worst " << first << " m; from 1 s after: " << settled << " m\n";
}

/// The written rows whose time is in (a, b].
std::vector<size_t> rowsIn(const FaultRun& r, double a, double b) {
    std::vector<size_t> v;
    for (size_t i = 0; i < r.trajectory.size(); ++i)
        if (r.trajectory[i].t > a && r.trajectory[i].t <= b) v.push_back(i);
    return v;
}

void report(const std::string& what, const FaultRun& r, double t_after) {
    std::cout << what << ": exit " << r.exit_code << ", " << r.trajectory.size() << " frames, worst before "
              << superloc::testing::maxWhere(r, [&](double t) { return t <= t_after; }) << " m, worst after "
              << superloc::testing::maxWhere(r, [&](double t) { return t > t_after; }) << " m\n";
}

}  // namespace

TEST_F(FaultsSim, CleanControl) {
    const FaultRun r = run("clean", keepAll);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.trajectory.size(), scanTimes().size());
    EXPECT_LT(superloc::testing::maxWhere(r, [](double) { return true; }), 0.03);  // measured 2.7 cm
    EXPECT_EQ(r.summary.at("status"), "ok");
    EXPECT_TRUE(r.summary.at("error").is_null());
}

// (1) No scan for 2 s, IMU and odom_alt go on: the first scan after the gap is predicted by 2 s
// of preintegrated IMU (measured 2.9 cm off after the solve; worst after the gap 3.3 cm).
TEST_F(FaultsSim, LidarDropout2s) {
    const double a = t0_ + kFault, b = a + 2.0;
    const FaultRun r = run("dropout", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        if (it.kind == io::RawlogItem::Kind::Lidar && it.time() > a + 1e-3 && it.time() <= b + 1e-3) return;
        writeItem(w, it);
    });
    report("dropout", r, b);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.trajectory.size(), scanTimes().size() - 20) << "every scan outside the dropout is a frame";
    EXPECT_TRUE(rowsIn(r, a + 1e-3, b + 1e-3).empty());
    const auto after = rowsIn(r, b + 1e-3, b + 0.15);
    ASSERT_EQ(after.size(), 1u);
    EXPECT_EQ(r.frames.num(after[0], "used_imu"), 1) << "predicted across the gap by the IMU";
    EXPECT_EQ(r.frames.num(after[0], "diverged"), 0);
    EXPECT_EQ(r.summary.at("frames_diverged"), 0);
    expectRecovered(r, b);
}

// (2) No IMU sample for 1 s: the scans whose interval touches the gap are predicted at constant
// velocity, without the IMU factor (used_imu 0; measured up to 9.2 cm off), and the IMU takes
// over again from the first interval after it (3.7 cm, then back to the clean envelope).
TEST_F(FaultsSim, ImuGap) {
    const double a = t0_ + kFault, b = a + 1.0;
    const FaultRun r = run("imu_gap", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        if (it.kind == io::RawlogItem::Kind::Imu && it.time() > a + 1e-3 && it.time() <= b + 1e-3) return;
        writeItem(w, it);
    });
    report("imu gap", r, b);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.trajectory.size(), scanTimes().size());
    size_t with_imu = 0;
    for (size_t i = 1; i < r.trajectory.size(); ++i) {
        // Predicted by the IMU when the samples around [t_prev, t] have no hole (the last sample
        // before the gap is at a, the first after it at b + 5 ms).
        const double t = r.trajectory[i].t, t_prev = r.trajectory[i - 1].t;
        const bool spans_gap = t > a + 1e-3 && t_prev < b + 0.005;
        EXPECT_EQ(r.frames.num(i, "used_imu"), spans_gap ? 0 : 1) << "t - t0 = " << t - t0_;
        EXPECT_EQ(r.frames.num(i, "diverged"), 0) << "t - t0 = " << t - t0_;
        with_imu += !spans_gap;
    }
    EXPECT_EQ(r.summary.at("frames_with_imu"), with_imu);
    EXPECT_LT(superloc::testing::maxWhere(r, [&](double t) { return t > a && t <= b + 0.15; }), 0.15)
        << "at constant velocity";
    expectRecovered(r, b + 0.15);  // from the first frame predicted by the IMU again
}

// (3) No odom_alt for 2 s (method passive, which fuses it on every frame it can): a frame gets
// the relative-pose prior only when odom_alt brackets both ends of its interval (samples at
// most 0.5 s apart), so the frames whose interval touches the gap go without it; a warning
// says when the gap starts and ends. Measured worst 2.9 cm in and after the gap.
TEST_F(FaultsSim, OdomAltGap) {
    const double a = t0_ + kFault, b = a + 2.0;
    const FaultRun r = run(
        "odom_gap",
        [&](io::RawlogItem& it, io::RawlogWriter& w) {
            if (it.kind == io::RawlogItem::Kind::OdomAlt && it.time() > a + 1e-3 && it.time() <= b + 1e-3) return;
            writeItem(w, it);
        },
        "passive");
    report("odom gap", r, b);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.trajectory.size(), scanTimes().size());
    size_t with_prior = 0;
    for (size_t i = 1; i < r.trajectory.size(); ++i) {
        const double t = r.trajectory[i].t, t_prev = r.trajectory[i - 1].t;
        const bool touches_gap = t > a + 1e-3 && t_prev < b + 0.05 - 1e-3;  // next sample: b + 1/20 Hz
        EXPECT_EQ(r.frames.num(i, "prior_used"), touches_gap ? 0 : 1) << "t - t0 = " << t - t0_;
        with_prior += !touches_gap;
    }
    EXPECT_EQ(r.summary.at("frames_with_prior"), with_prior);
    EXPECT_LT(superloc::testing::maxWhere(r, [&](double t) { return t > a && t <= b; }), kRecoveredM);
    expectRecovered(r, b);
}

// (4a) An observation older than the reorder window (a scan re-sent 2 s late, as after a clock
// step): the reader cannot place it, so the run stops with one line on stderr and exit code 1.
// Every scan read before it is localized and in trajectory.tum and frames.csv (the reader
// empties its reorder_window = 0.5 s re-sort window before it reports the error), and
// summary.json says "failed" and why.
TEST_F(FaultsSim, BackwardsTimestampBeyondWindow) {
    const double a = t0_ + kFault;
    double t_newest = 0;
    bool done = false;
    const FaultRun r = run("backwards", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        writeItem(w, it);
        if (!done) t_newest = std::max(t_newest, it.time());
        if (!done && it.kind == io::RawlogItem::Kind::Lidar && it.time() > a + 1e-3) {
            io::RawlogItem old = it;
            std::get<Scan>(old.data).t -= 2.0;
            writeItem(w, old);
            done = true;
        }
    });
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.stderr_text.find("timestamp goes backwards by 2.0"), std::string::npos) << r.stderr_text;
    // Processed: every scan written before the backwards one, in order, and nothing else.
    std::vector<double> expected;
    for (double t : scanTimes())
        if (t <= t_newest + 1e-6) expected.push_back(t);
    ASSERT_EQ(r.trajectory.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(r.trajectory[i].t, expected[i], 1e-6);
    EXPECT_LT(superloc::testing::maxWhere(r, [](double) { return true; }), 0.03);
    EXPECT_EQ(r.summary.at("status"), "failed");
    EXPECT_NE(r.summary.at("error").get<std::string>().find("reorder_window"), std::string::npos);
    EXPECT_EQ(r.summary.at("frames"), expected.size());
    EXPECT_TRUE(fs::exists(r.dir + "/localized_map.pcd"));
}

// (4b) A scan written after the next one (0.1 s out of order, inside the 0.5 s reorder window)
// is put back in place by the reader: the run is the clean run, pose for pose.
TEST_F(FaultsSim, BackwardsTimestampWithinWindow) {
    const double a = t0_ + kFault;
    std::optional<io::RawlogItem> held;
    bool done = false;
    const FaultRun r = run("swapped", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        if (!done && it.kind == io::RawlogItem::Kind::Lidar && it.time() > a + 1e-3) {
            done = true;
            held = it;
            return;
        }
        writeItem(w, it);
        if (held && it.kind == io::RawlogItem::Kind::Lidar) {
            writeItem(w, *held);
            held.reset();
        }
    });
    const FaultRun clean = run("clean", keepAll);
    EXPECT_EQ(r.exit_code, 0);
    ASSERT_EQ(r.trajectory.size(), clean.trajectory.size());
    for (size_t i = 0; i < r.trajectory.size(); ++i) {
        EXPECT_EQ(r.trajectory[i].t, clean.trajectory[i].t);
        EXPECT_LT(translationDistance(r.trajectory[i].pose, clean.trajectory[i].pose), 1e-9) << i;
    }
}

// (5) NaN/inf floods: one scan entirely NaN/inf, the next one 95 % NaN/inf. The reader drops
// invalid points (counted, one warning: not on stderr with --quiet); the all-NaN scan has
// nothing left and is skipped (counted as rawlog.scans_empty_skipped in summary.json, no
// frame), the other is localized from its 5 % (2477 points; 0.7 cm off).
TEST_F(FaultsSim, NanFloodedScan) {
    const double a = t0_ + kFault;
    int n = 0;
    size_t points = 0;
    const FaultRun r = run("nan", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        if (it.kind == io::RawlogItem::Kind::Lidar && it.time() > a + 1e-3 && n < 2) {
            auto& s = std::get<Scan>(it.data);
            points += s.points.size();
            for (size_t i = 0; i < s.points.size(); ++i)
                if (n == 0 || i % 20 != 0) s.points[i].setConstant(i % 3 ? NAN : INFINITY);
            ++n;
        }
        writeItem(w, it);
    });
    report("nan", r, a);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.trajectory.size(), scanTimes().size() - 1);
    EXPECT_TRUE(rowsIn(r, a + 1e-3, a + 0.15).empty()) << "the all-NaN scan makes no frame";
    const auto sparse = rowsIn(r, a + 0.15, a + 0.25);
    ASSERT_EQ(sparse.size(), 1u);
    EXPECT_LT(r.frames.num(sparse[0], "points_raw"), 0.06 * static_cast<double>(points) / 2);
    EXPECT_EQ(r.frames.num(sparse[0], "diverged"), 0);
    const auto& rs = r.summary.at("rawlog");
    EXPECT_EQ(rs.at("scans_empty_skipped"), 1);
    EXPECT_EQ(rs.at("scans_read"), scanTimes().size() - 1);
    EXPECT_GT(rs.at("invalid_points_dropped").get<double>(), 0.9 * static_cast<double>(points));
    EXPECT_EQ(r.summary.at("frames_diverged"), 0);
    expectRecovered(r, a);
}

// (6) A scan of 5 points: fewer than the 10 correspondences a scan factor needs, so with the
// IMU the frame is the IMU-only solve (reported with 5 points and at most 5 features; 0.6 cm
// off here), and the next scan is tracked as usual.
TEST_F(FaultsSim, FivePointScan) {
    const double a = t0_ + kFault;
    bool done = false;
    const FaultRun r = run("five", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        if (!done && it.kind == io::RawlogItem::Kind::Lidar && it.time() > a + 1e-3) {
            auto& s = std::get<Scan>(it.data);
            std::vector<Vec3f> p;
            for (size_t k = 0; k < 5; ++k) p.push_back(s.points[k * (s.points.size() / 5)]);
            s.points = p;
            s.intensity.clear();
            done = true;
        }
        writeItem(w, it);
    });
    report("five", r, a);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.trajectory.size(), scanTimes().size());
    const auto five = rowsIn(r, a + 1e-3, a + 0.15);
    ASSERT_EQ(five.size(), 1u);
    EXPECT_EQ(r.frames.num(five[0], "points_raw"), 5);
    EXPECT_LE(r.frames.num(five[0], "features"), 5);
    EXPECT_EQ(r.frames.num(five[0], "used_imu"), 1);
    EXPECT_LT(r.err_m[five[0]], kRecoveredM);
    expectRecovered(r, a);
}

// (1+2) A LiDAR dropout over an IMU gap: the interval from the last scan before to the first
// after has a 1 s hole in the IMU data. Before the fix the prediction bridged it with the last
// sample before the hole (integrateInterval holds each sample until the next) and the rest of
// the run stayed 0.7-1.1 m off without a single frame flagged; now imu::coversInterval() sees
// the hole, the frame is predicted at constant velocity and solved wide (coarse start, more than
// max_cv_gap since the last frame): 2.7 cm, worst after the gap 4.4 cm.
TEST_F(FaultsSim, LidarDropoutOverImuGap) {
    const double a = t0_ + kFault, b = a + 2.0;
    const FaultRun r = run("dropout_imu_gap", [&](io::RawlogItem& it, io::RawlogWriter& w) {
        if (it.kind == io::RawlogItem::Kind::Lidar && it.time() > a + 1e-3 && it.time() <= b + 1e-3) return;
        if (it.kind == io::RawlogItem::Kind::Imu && it.time() > a + 0.5 && it.time() <= a + 1.5) return;
        writeItem(w, it);
    });
    report("dropout over an IMU gap", r, b);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.trajectory.size(), scanTimes().size() - 20);
    const auto after = rowsIn(r, b + 1e-3, b + 0.15);
    ASSERT_EQ(after.size(), 1u);
    EXPECT_EQ(r.frames.num(after[0], "used_imu"), 0) << "the IMU has a hole in this interval";
    // Measured with the relocalization (doc/health.md): the frame after the gap (constant
    // velocity over 2 s, no IMU) lands 2.3 m off and says so (degraded: its local search finds
    // the office's look-alike rooms as well, ambiguous, and commits to none); so do the next
    // nine (1.8-2.3 m off, degraded, ambiguous); the 11th is relocalized (2.7 cm) and keeps its
    // tracked velocity, and from then on the clean envelope holds. Never confidently wrong.
    for (size_t i = 0; i < r.trajectory.size(); ++i)
        if (r.err_m[i] > 0.5) {
            EXPECT_NE(r.frames.text(i, "health"), "ok") << "frame " << i << " " << r.err_m[i] << " m off, ok";
        }
    const double settled = superloc::testing::maxWhere(r, [&](double t) { return t > b + 1.0; });
    EXPECT_LT(settled, kSettledM) << "worst frame from 1 s after the fault";
}
