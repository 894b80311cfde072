// Bags as robots record them (issue 29), in every format (ROS 1 .bag when built, ROS 2 .db3 and
// MCAP): LiDAR header stamps left at 0 ([rosbag] stamp_source), an IMU or ground truth on a clock
// far from the LiDAR's ([rosbag] max_clock_offset), an empty frame_id. The bags come from one
// description, tests/support/superloc_testing/recorded_bag.h.
#include <superloc/io/rawlog.h>
#include <superloc/io/rosbag.h>
#include <superloc_testing/recorded_bag.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <cstring>
#include <filesystem>

namespace {

using namespace superloc;
using namespace superloc::io;
namespace bw = superloc::testing::bag;
using bw::kRecT0;
using superloc::testing::errorOf;

const double kT0 = double(kRecT0) * 1e-9;

/// The formats this build reads.
std::vector<std::string> formats() {
#ifdef SUPERLOC_HAVE_ROS1
    return {"bag", "db3", "mcap"};
#else
    return {"db3", "mcap"};
#endif
}

/// `rec` written as DIR/NAME.FORMAT.
std::string write(const std::string& dir, const std::string& name, const std::string& format,
                  const bw::Recording& rec) {
    const std::string path = dir + "/" + name + "." + format;
    if (format == "db3") bw::writeDb3(path, bw::ros2Messages(rec));
    if (format == "mcap") bw::writeMcap(path, bw::ros2Messages(rec));
#ifdef SUPERLOC_HAVE_ROS1
    if (format == "bag") bw::writeRos1Recording(path, rec);
#endif
    return path;
}

struct Imported {
    std::vector<Scan> scans;
    std::vector<ImuSample> imu;
    std::vector<PoseStamped> gt;
};

Imported readBack(const std::string& rawlog) {
    RawlogParams rp;
    rp.scan_period = 0;  // only what the rawlog carries
    RawlogReader reader(rawlog, rp);
    Imported out;
    RawlogItem it;
    while (reader.next(it)) {
        if (it.kind == RawlogItem::Kind::Lidar) out.scans.push_back(it.scan());
        if (it.kind == RawlogItem::Kind::Imu) out.imu.push_back(it.imu());
        if (it.kind == RawlogItem::Kind::GroundTruth) out.gt.push_back(it.pose());
    }
    return out;
}

/// One line, starting with the bag, holding every part.
void expectError(const std::string& e, const std::string& bag, const std::vector<std::string>& parts) {
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(e.rfind(bag + ": ", 0), 0u) << e;
    for (const auto& p : parts) EXPECT_NE(e.find(p), std::string::npos) << "missing <<" << p << ">> in " << e;
}

}  // namespace

TEST(BagClocks, ZeroedLidarStampsImportEveryScanOnTheRecordTime) {
    const auto dir = superloc::testing::freshDir("bag_clocks_zero");
    bw::Recording rec;
    rec.lidar_stamps = false;  // the IMU's header clock is the recorder's (2 ms latency)
    for (const auto& f : formats()) {
        SCOPED_TRACE(f);
        const std::string bag = write(dir, "zero", f, rec);
        // auto: the LiDAR on the record time (with the reason), the IMU keeps header.stamp.
        const auto r = importRosbag(bag, {}, bag + ".auto.rawlog");
        EXPECT_EQ(r.scans, 12u);
        EXPECT_EQ(r.timed_scans, 12u);
        EXPECT_EQ(r.imu, 131u);
        EXPECT_TRUE(r.non_monotonic.empty());
        ASSERT_EQ(r.stamps.size(), 2u);
        EXPECT_EQ(r.stamps[0].topic, "/points");
        EXPECT_TRUE(r.stamps[0].record_time);
        EXPECT_EQ(r.stamps[0].reason, "header.stamp is 0 on 12 of 12 messages");
        EXPECT_EQ(r.stamps[1].topic, "/imu");
        EXPECT_FALSE(r.stamps[1].record_time);
        EXPECT_EQ(r.stamps[1].reason, "");
        const auto a = readBack(bag + ".auto.rawlog");
        ASSERT_EQ(a.scans.size(), 12u);
        for (size_t k = 0; k < 12; ++k) {
            EXPECT_NEAR(a.scans[k].t - kT0, 0.1 * k + 0.06, 1e-6) << k;  // recorded 60 ms late
            ASSERT_EQ(a.scans[k].rel_time.size(), 100u);
            EXPECT_NEAR(a.scans[k].rel_time[99], 0.099, 1e-6);  // relative times as recorded
            EXPECT_NEAR(a.scans[k].rel_time[0], 0.0, 1e-6);
        }
        ASSERT_EQ(a.imu.size(), 131u);
        EXPECT_NEAR(a.imu[0].t - kT0, -0.05, 1e-6);  // header.stamp, not the record time

        // header: today's behaviour, the LiDAR alone: the first scan, 11 skipped.
        RosbagParams p;
        p.stamp_source = "header";
        p.imu_topic = "none";
        const auto h = importRosbag(bag, p, bag + ".header.rawlog");
        EXPECT_EQ(h.scans, 1u);
        ASSERT_EQ(h.non_monotonic.size(), 1u);
        EXPECT_EQ(h.non_monotonic[0], (std::pair<std::string, size_t>{"/points", 11}));
        EXPECT_FALSE(h.stamps[0].record_time);
        // header with the IMU: scans at 0 s and an IMU at 1.7e9 s do not overlap.
        p.imu_topic = "";
        expectError(errorOf([&] { importRosbag(bag, p, bag + ".x.rawlog"); }), bag,
                    {"topic '/points' (header.stamp, 0.000 to 0.000 s) and topic '/imu' "
                     "(header.stamp, 1699999999.950 to 1700000001.250 s) do not overlap",
                     "stamp_source = record"});

        // record: every topic on the record time.
        p.stamp_source = "record";
        const auto rr = importRosbag(bag, p, bag + ".record.rawlog");
        EXPECT_EQ(rr.scans, 12u);
        EXPECT_TRUE(rr.stamps[1].record_time);
        EXPECT_EQ(rr.stamps[1].reason, "");  // asked for, not chosen by auto
        const auto c = readBack(bag + ".record.rawlog");
        ASSERT_EQ(c.imu.size(), 131u);
        EXPECT_NEAR(c.imu[0].t - kT0, -0.048, 1e-6);
        EXPECT_NEAR(c.scans[3].t - kT0, 0.36, 1e-6);
    }
}

TEST(BagClocks, LidarAndImuClocksThatDisagreeAreAnErrorNamingBoth) {
    const auto dir = superloc::testing::freshDir("bag_clocks_disagree");
    for (const auto& f : formats()) {
        SCOPED_TRACE(f);
        // The IMU's header clock 3 days behind the recorder's.
        bw::Recording rec;
        rec.imu_clock_offset_ns = -259200LL * 1000000000LL;
        std::string bag = write(dir, "days", f, rec);
        expectError(errorOf([&] { importRosbag(bag, {}, bag + ".rawlog"); }), bag,
                    {"the times of topic '/points' (header.stamp, 1700000000.000 to "
                     "1700000001.100 s) and topic '/imu' (header.stamp, 1699740799.950 to "
                     "1699740801.250 s) do not overlap and their clocks differ by 259199.942 s "
                     "against the bag's record time",
                     "set [rosbag] stamp_source = record"});
        EXPECT_FALSE(std::filesystem::exists(bag + ".rawlog"));  // checked before writing
        RosbagParams p;
        p.stamp_source = "record";
        auto r = importRosbag(bag, p, bag + ".rawlog");
        EXPECT_EQ(r.scans, 12u);
        EXPECT_EQ(r.imu, 131u);
        p.stamp_source = "auto";
        p.max_clock_offset = 0;  // no check: imported as recorded
        EXPECT_EQ(importRosbag(bag, p, bag + ".rawlog").imu, 131u);

        // Overlapping, but the IMU's clock 0.5 s ahead: within the default 1 s, not within 0.3 s.
        rec.imu_clock_offset_ns = 500000000;
        bag = write(dir, "half", f, rec);
        EXPECT_EQ(importRosbag(bag, {}, bag + ".rawlog").imu, 131u);
        p.max_clock_offset = 0.3;
        expectError(errorOf([&] { importRosbag(bag, p, bag + ".rawlog"); }), bag,
                    {"topic '/points' (header.stamp", "topic '/imu' (header.stamp",
                     "overlap, but their clocks differ by 0.558 s against the bag's record time "
                     "(more than [rosbag] max_clock_offset = 0.3 s)"});

        // Ground truth on another clock (one hour ahead), checked the same way.
        rec = bw::Recording();
        rec.gt = true;
        rec.gt_clock_offset_ns = 3600LL * 1000000000LL;
        bag = write(dir, "gt", f, rec);
        RosbagParams g;
        g.gt_topic = "/gt";
        expectError(errorOf([&] { importRosbag(bag, g, bag + ".rawlog"); }), bag,
                    {"topic '/points' (header.stamp", "and topic '/gt' (header.stamp",
                     "do not overlap"});
        rec.gt_clock_offset_ns = 0;
        bag = write(dir, "gt-ok", f, rec);
        EXPECT_EQ(importRosbag(bag, g, bag + ".rawlog").gt_poses, 12u);
    }
}

TEST(BagClocks, EmptyFrameIdIsAMissingTransformNamingTheTopic) {
    const auto dir = superloc::testing::freshDir("bag_clocks_frames");
    const SE3d T_imu_lidar = bw::kT_base_imu.inverse() * bw::kT_base_lidar;
    for (const auto& f : formats()) {
        SCOPED_TRACE(f);
        // LiDAR without a frame, IMU in imu_link: T_imu_lidar cannot be looked up.
        bw::Recording rec;
        rec.lidar_frame = "";
        std::string bag = write(dir, "nolidarframe", f, rec);
        expectError(errorOf([&] { importRosbag(bag, {}, bag + ".rawlog"); }), bag,
                    {"topic '/points': empty header.frame_id, so no static transform from "
                     "'imu_link' to the LiDAR can be looked up (set [rosbag] lidar_extrinsic)"});
        RosbagParams p;
        p.lidar_extrinsic = "1 2 3 0 0 0 1";
        importRosbag(bag, p, bag + ".rawlog");
        EXPECT_TRUE(readBack(bag + ".rawlog").scans.at(0).T_imu_lidar.translation().isApprox(
            Vec3d(1, 2, 3)));

        // The same LiDAR alone: its own frame is the body, no transform needed.
        p = RosbagParams();
        p.imu_topic = "none";
        importRosbag(bag, p, bag + ".rawlog");
        EXPECT_TRUE(readBack(bag + ".rawlog").scans.at(0).T_imu_lidar.isApprox(SE3d::Identity()));
        // ... but ground truth of base_link needs T_base_lidar.
        rec.imu = false;
        rec.gt = true;
        bag = write(dir, "nolidarframe-gt", f, rec);
        p.gt_topic = "/gt";
        expectError(errorOf([&] { importRosbag(bag, p, bag + ".rawlog"); }), bag,
                    {"topic '/gt': no static transform from its child frame 'base_link' to the "
                     "LiDAR: topic '/points' has an empty header.frame_id (set [rosbag] "
                     "body_frame and lidar_extrinsic)"});
        p.body_frame = "base_link";
        p.lidar_extrinsic = "0.3 0 1.2 0 0 0 1";
        importRosbag(bag, p, bag + ".rawlog");
        const auto gt = readBack(bag + ".rawlog").gt;
        ASSERT_EQ(gt.size(), 12u);
        EXPECT_TRUE(gt[2].pose.translation().isApprox(Vec3d(1.0 + 0.3, 0, 1.2), 1e-9));

        // IMU without a frame: the body frame is unknown, unless named.
        rec = bw::Recording();
        rec.imu_frame = "";
        bag = write(dir, "noimuframe", f, rec);
        expectError(errorOf([&] { importRosbag(bag, {}, bag + ".rawlog"); }), bag,
                    {"topic '/imu': empty header.frame_id, so the body (IMU) frame is unknown "
                     "(set [rosbag] body_frame"});
        p = RosbagParams();
        p.body_frame = "imu_link";
        importRosbag(bag, p, bag + ".rawlog");
        EXPECT_TRUE(readBack(bag + ".rawlog").scans.at(0).T_imu_lidar.isApprox(T_imu_lidar, 1e-9));
    }
}

// A driver that leaves header.stamp unset but gives every point its absolute time (float64
// `timestamp`, on the recorder's clock, the sweep ending 50 ms before the scan is recorded): on
// the record time, the point times are read as absolute and kept relative to the scan's time.
TEST(BagClocks, AbsolutePointTimesOfAnUnsetStampAreReadAgainstTheRecordTime) {
    const auto dir = superloc::testing::freshDir("bag_clocks_abs");
    const int64_t rec_ns = kRecT0 + 60000000;
    bw::Cloud c = bw::recordedCloud(0, {0, 0}, "lidar");
    c.point_step = 24;
    c.row_step = c.width * 24;
    c.fields.back() = {"timestamp", 16, 8, 1};
    std::vector<uint8_t> data(c.width * 24);
    for (size_t i = 0; i < c.width; ++i) {
        std::memcpy(&data[i * 24], &c.data[i * 20], 16);
        const double t = double(rec_ns) * 1e-9 - 0.15 + 1e-3 * double(i);
        std::memcpy(&data[i * 24 + 16], &t, 8);
    }
    c.data = data;
    const std::string bag = dir + "/abs.mcap";
    bw::writeMcap(bag, {{"/points", "sensor_msgs/msg/PointCloud2", rec_ns, bw::cdr(c)}});
    RosbagParams p;
    p.lidar_extrinsic = "0 0 0 0 0 0 1";
    const auto r = importRosbag(bag, p, bag + ".rawlog");
    EXPECT_EQ(r.timed_scans, 1u);
    EXPECT_EQ(r.time_field, "timestamp");
    const auto s = readBack(bag + ".rawlog").scans;
    ASSERT_EQ(s.size(), 1u);
    EXPECT_NEAR(s[0].t - kT0, 0.06, 1e-6);
    ASSERT_EQ(s[0].rel_time.size(), c.width);
    for (size_t i = 0; i < c.width; i += 33)
        EXPECT_NEAR(s[0].rel_time[i], -0.15 + 1e-3 * double(i), 1e-6) << i;
}
