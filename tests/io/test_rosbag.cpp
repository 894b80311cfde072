// ROS 1 bags: the shared kitti00-mini.bag (written by ROS's own Python rosbag) against the KITTI
// importer, a round trip through a bag written here with rosbag_storage, and bad input.
#ifdef SUPERLOC_HAVE_ROS1

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <superloc/core/se3.h>
#include <superloc/io/importers.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/rosbag.h>
#include <superloc/io/tum.h>
#include <superloc_testing/bag_content.h>
#include <superloc_testing/testing.h>
#include <tf2_msgs/TFMessage.h>

#include <cstring>
#include <filesystem>
#include <fstream>

namespace {

using namespace superloc;
using superloc::testing::bag::kT_base_imu;
using superloc::testing::bag::kT_base_lidar;
using superloc::testing::bag::symCov;
using namespace superloc::io;

std::vector<RawlogItem> readAll(const std::string& path) {
    RawlogParams rp;
    rp.scan_period = 0;  // no azimuth-derived time: only what the rawlog carries
    RawlogReader r(path, rp);
    std::vector<RawlogItem> items;
    RawlogItem it;
    while (r.next(it)) items.push_back(it);
    return items;
}

using superloc::testing::errorOf;

// --- bag writing helpers ---------------------------------------------------------------------

ros::Time rosTime(double t) {
    ros::Time r;
    r.fromSec(t);
    return r;
}

geometry_msgs::TransformStamped tfMsg(const std::string& parent, const std::string& child,
                                      const SE3d& T) {
    geometry_msgs::TransformStamped x;
    x.header.frame_id = parent;
    x.child_frame_id = child;
    x.transform.translation.x = T.translation().x();
    x.transform.translation.y = T.translation().y();
    x.transform.translation.z = T.translation().z();
    const Eigen::Quaterniond q(T.rotation());
    x.transform.rotation.x = q.x();
    x.transform.rotation.y = q.y();
    x.transform.rotation.z = q.z();
    x.transform.rotation.w = q.w();
    return x;
}

void setPose(geometry_msgs::Pose& p, const SE3d& T) {
    p.position.x = T.translation().x();
    p.position.y = T.translation().y();
    p.position.z = T.translation().z();
    const Eigen::Quaterniond q(T.rotation());
    p.orientation.x = q.x();
    p.orientation.y = q.y();
    p.orientation.z = q.z();
    p.orientation.w = q.w();
}

sensor_msgs::PointField field(const std::string& name, uint32_t offset, uint8_t type) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = type;
    f.count = 1;
    return f;
}

/// A cloud of n points, fields x y z intensity (float32) and `t` (uint32 ns, relative).
sensor_msgs::PointCloud2 cloud(double stamp, size_t n, const std::string& frame, bool with_xyz = true) {
    sensor_msgs::PointCloud2 pc;
    pc.header.stamp = rosTime(stamp);
    pc.header.frame_id = frame;
    pc.height = 1;
    pc.width = uint32_t(n);
    pc.point_step = 20;
    pc.row_step = pc.point_step * pc.width;
    pc.fields = {field(with_xyz ? "x" : "a", 0, 7), field(with_xyz ? "y" : "b", 4, 7),
                 field(with_xyz ? "z" : "c", 8, 7), field("intensity", 12, 7), field("t", 16, 6)};
    pc.data.resize(pc.row_step);
    for (size_t i = 0; i < n; ++i) {
        const float v[4] = {float(1 + i), float(-2.5 + 0.25 * i), float(0.125 * i), float(i % 200)};
        const uint32_t t_ns = uint32_t(i * 1000000);  // 1 ms per point
        std::memcpy(&pc.data[i * 20], v, 16);
        std::memcpy(&pc.data[i * 20 + 16], &t_ns, 4);
    }
    return pc;
}


/// Round-trip bag: tf_static base_link -> lidar, base_link -> imu_link; 3 timed scans; 20 IMU
/// samples; odometry with covariance; PoseStamped ground truth (child base_link via INI).
void writeRoundTripBag(const std::string& path) {
    rosbag::Bag b(path, rosbag::bagmode::Write);
    tf2_msgs::TFMessage tf;
    tf.transforms = {tfMsg("base_link", "lidar", kT_base_lidar),
                     tfMsg("base_link", "imu_link", kT_base_imu)};
    b.write("/tf_static", rosTime(100.0), tf);
    for (int k = 0; k < 20; ++k) {
        sensor_msgs::Imu imu;
        imu.header.stamp = rosTime(100.0 + 0.01 * k);
        imu.header.frame_id = "imu_link";
        imu.linear_acceleration.x = 0.1 * k;
        imu.linear_acceleration.y = -0.2;
        imu.linear_acceleration.z = 9.81;
        imu.angular_velocity.x = 0.01;
        imu.angular_velocity.y = -0.02 * k;
        imu.angular_velocity.z = 0.5;
        b.write("/imu", imu.header.stamp, imu);
    }
    for (int k = 0; k < 3; ++k) {
        const double t = 100.0 + 0.1 * k;
        b.write("/points", rosTime(t), cloud(t, 50 + k, "lidar"));
        nav_msgs::Odometry o;
        o.header.stamp = rosTime(t);
        o.header.frame_id = "odom";
        o.child_frame_id = "base_link";
        setPose(o.pose.pose, makePoseRPY(k * 0.5, 0.1 * k, 0, 0, 0, 0.1 * k));
        for (size_t i = 0; i < 36; ++i) o.pose.covariance[i] = symCov(i, k);
        b.write("/odom", o.header.stamp, o);
        geometry_msgs::PoseStamped g;
        g.header.stamp = rosTime(t);
        g.header.frame_id = "map";
        setPose(g.pose, makePoseRPY(10 + k * 0.5, 5, 1, 0.01, 0, 0.2 + 0.1 * k));
        b.write("/gt", g.header.stamp, g);
    }
    b.close();
}

RosbagParams roundTripParams() {
    RosbagParams p;
    p.lidar_topic = "/points";
    p.odom_alt_topic = "/odom";
    p.gt_topic = "/gt";
    p.gt_child_frame = "base_link";
    return p;  // body frame: the IMU's (imu_link)
}

}  // namespace

TEST(Rosbag, KittiBagImportsLikeKittiFolder) {
    SUPERLOC_REQUIRE_DATA("rosbag-kitti00-mini/kitti00-mini.bag");
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("rosbag_kitti");
    const auto kitti = superloc::testing::sharedData("kitti00-mini");
    RosbagParams p;
    p.gt_topic = "/ground_truth";
    const auto rb = importRosbag(superloc::testing::sharedData("rosbag-kitti00-mini/kitti00-mini.bag"), p,
                                 dir + "/bag.rawlog");
    const auto rk = importKitti(kitti, "", "", dir + "/kitti.rawlog");
    EXPECT_EQ(rb.scans, 16u);
    EXPECT_EQ(rb.points, rk.points);
    EXPECT_EQ(rb.gt_poses, 16u);
    const auto bag = readAll(dir + "/bag.rawlog");
    const auto kit = readAll(dir + "/kitti.rawlog");
    std::vector<const Scan*> bs, ks;
    std::vector<const PoseStamped*> bg;
    for (const auto& it : bag)
        if (it.kind == RawlogItem::Kind::Lidar)
            bs.push_back(&it.scan());
        else if (it.kind == RawlogItem::Kind::GroundTruth)
            bg.push_back(&it.pose());
    for (const auto& it : kit)
        if (it.kind == RawlogItem::Kind::Lidar) ks.push_back(&it.scan());
    ASSERT_EQ(bs.size(), 16u);
    ASSERT_EQ(ks.size(), 16u);
    double max_dt = 0;
    for (size_t i = 0; i < 16; ++i) {
        // Points and intensities bit-identical; the body frame is the LiDAR's (no IMU).
        ASSERT_EQ(bs[i]->points.size(), ks[i]->points.size()) << i;
        EXPECT_EQ(std::memcmp(bs[i]->points.data(), ks[i]->points.data(),
                              ks[i]->points.size() * sizeof(Vec3f)), 0) << i;
        EXPECT_EQ(bs[i]->intensity, ks[i]->intensity) << i;
        EXPECT_TRUE(bs[i]->rel_time.empty());
        EXPECT_TRUE(bs[i]->T_imu_lidar.isApprox(SE3d::Identity()));
        // Stamps are KITTI times + 1e9 s, rounded by Python's double: equal to MRPT's 100 ns.
        max_dt = std::max(max_dt, std::abs((bs[i]->t - 1e9) - ks[i]->t));
    }
    EXPECT_LE(max_dt, 2e-7);
    std::cout << "[ kitti bag ] max |t_bag - 1e9 - t_kitti| = " << max_dt << " s\n";
    // Ground truth: base_link poses * T_base_velodyne (tf_static) = gt_velodyne_tum.txt.
    const auto gt = loadTum(kitti + "/gt_velodyne_tum.txt");
    ASSERT_EQ(bg.size(), gt.size());
    double max_dp = 0, max_dr = 0;
    for (size_t i = 0; i < gt.size(); ++i) {
        max_dp = std::max(max_dp, translationDistance(bg[i]->pose, gt[i].pose));
        max_dr = std::max(max_dr, rotationAngle(bg[i]->pose, gt[i].pose));
    }
    std::cout << "[ kitti bag ] gt vs gt_velodyne_tum: max " << max_dp << " m, " << max_dr
              << " rad\n";
    EXPECT_LT(max_dp, 1e-5);
    EXPECT_LT(max_dr, 1e-6);
}

TEST(Rosbag, ListsTopics) {
    const auto dir = superloc::testing::freshDir("rosbag_list");
    writeRoundTripBag(dir + "/rt.bag");
    const auto topics = listRosbag(dir + "/rt.bag");
    ASSERT_EQ(topics.size(), 5u);
    EXPECT_EQ(topics[0].topic, "/gt");
    EXPECT_EQ(topics[0].type, "geometry_msgs/PoseStamped");
    EXPECT_EQ(topics[1].topic, "/imu");
    EXPECT_EQ(topics[1].messages, 20u);
}

TEST(Rosbag, RoundTripEveryField) {
    const auto dir = superloc::testing::freshDir("rosbag_roundtrip");
    writeRoundTripBag(dir + "/rt.bag");
    const auto r = importRosbag(dir + "/rt.bag", roundTripParams(), dir + "/rt.rawlog");
    EXPECT_EQ(r.scans, 3u);
    EXPECT_EQ(r.timed_scans, 3u);
    EXPECT_EQ(r.time_field, "t");
    EXPECT_EQ(r.imu, 20u);
    EXPECT_EQ(r.odom_alt, 3u);
    EXPECT_EQ(r.gt_poses, 3u);
    EXPECT_TRUE(r.non_monotonic.empty());
    const SE3d T_imu_lidar = kT_base_imu.inverse() * kT_base_lidar;
    size_t scans = 0, imus = 0, odoms = 0, gts = 0;
    for (const auto& it : readAll(dir + "/rt.rawlog")) {
        switch (it.kind) {
            case RawlogItem::Kind::Lidar: {
                const Scan& s = it.scan();
                const auto ref = cloud(100.0 + 0.1 * scans, 50 + scans, "lidar");
                ASSERT_EQ(s.size(), 50 + scans);
                EXPECT_NEAR(s.t, 100.0 + 0.1 * scans, 1e-6);
                EXPECT_TRUE(s.T_imu_lidar.isApprox(T_imu_lidar, 1e-9));
                for (size_t i = 0; i < s.size(); ++i) {
                    float v[4];
                    std::memcpy(v, &ref.data[i * 20], 16);
                    EXPECT_EQ(s.points[i], Vec3f(v[0], v[1], v[2])) << i;
                    // intensity 0..255 as a byte (intensity_max 255), read back as byte / 255
                    EXPECT_FLOAT_EQ(s.intensity[i], v[3] / 255.0f) << i;
                    EXPECT_NEAR(s.rel_time[i], i * 1e-3, 1e-7) << i;  // 100 ns clock
                }
                ++scans;
                break;
            }
            case RawlogItem::Kind::Imu: {
                superloc::testing::bag::expectImu(it.imu(), int(imus), 100.0);
                ++imus;
                break;
            }
            case RawlogItem::Kind::OdomAlt: {
                superloc::testing::bag::expectOdomAlt(it.pose(), int(odoms));
                ++odoms;
                break;
            }
            case RawlogItem::Kind::GroundTruth: {
                superloc::testing::bag::expectGroundTruth(it.pose(), int(gts));  // T_map_lidar
                ++gts;
                break;
            }
        }
    }
    EXPECT_EQ(scans, 3u);
    EXPECT_EQ(imus, 20u);
    EXPECT_EQ(odoms, 3u);
    EXPECT_EQ(gts, 3u);
}

TEST(Rosbag, ExtrinsicFromIniAndBodyFrame) {
    const auto dir = superloc::testing::freshDir("rosbag_extrinsic");
    writeRoundTripBag(dir + "/rt.bag");
    auto p = roundTripParams();
    p.imu_topic = "none";
    p.odom_alt_topic = "none";
    p.gt_topic = "none";
    p.body_frame = "base_link";
    importRosbag(dir + "/rt.bag", p, dir + "/a.rawlog");
    const auto a = readAll(dir + "/a.rawlog");
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(a[0].scan().T_imu_lidar.isApprox(kT_base_lidar, 1e-9));
    p.lidar_extrinsic = "1 2 3 0 0 0 1";
    importRosbag(dir + "/rt.bag", p, dir + "/b.rawlog");
    const auto b = readAll(dir + "/b.rawlog");
    EXPECT_TRUE(b[0].scan().T_imu_lidar.translation().isApprox(Vec3d(1, 2, 3)));
}

TEST(Rosbag, BadInputIsOneLineNamingFileAndTopic) {
    const auto dir = superloc::testing::freshDir("rosbag_bad");
    const std::string bag = dir + "/rt.bag";
    writeRoundTripBag(bag);
    const auto oneLine = [](const std::string& e) { return e.find('\n') == std::string::npos; };

    // Missing file, missing topic, wrong type on a mapped topic.
    auto e = errorOf([&] { importRosbag(dir + "/nope.bag", {}, dir + "/x.rawlog"); });
    EXPECT_NE(e.find(dir + "/nope.bag"), std::string::npos) << e;
    auto p = roundTripParams();
    p.gt_topic = "/ground_truth";
    e = errorOf([&] { importRosbag(bag, p, dir + "/x.rawlog"); });
    EXPECT_NE(e.find(bag + ": topic '/ground_truth' ([rosbag] gt_topic) is not in the bag"),
              std::string::npos) << e;
    p = roundTripParams();
    p.odom_alt_topic = "/imu";
    e = errorOf([&] { importRosbag(bag, p, dir + "/x.rawlog"); });
    EXPECT_NE(e.find(bag + ": topic '/imu' ([rosbag] odom_alt_topic) is sensor_msgs/Imu, "
                           "expected nav_msgs/Odometry"),
              std::string::npos) << e;
    EXPECT_TRUE(oneLine(e));

    // Truncated bag: the first half of the file.
    {
        std::ifstream in(bag, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), {});
        std::ofstream(dir + "/trunc.bag", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    }
    e = errorOf([&] { importRosbag(dir + "/trunc.bag", roundTripParams(), dir + "/x.rawlog"); });
    EXPECT_NE(e.find(dir + "/trunc.bag: "), std::string::npos) << e;
    EXPECT_TRUE(oneLine(e)) << e;

    // Unknown chunk compression: every chunk header's "compression=none" made "compression=zzzz".
    {
        std::ifstream in(bag, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), {});
        const std::string from = "compression=none", to = "compression=zzzz";
        size_t n = 0;
        for (size_t pos = 0; (pos = bytes.find(from, pos)) != std::string::npos; ++n)
            bytes.replace(pos, from.size(), to);
        EXPECT_GT(n, 0u);
        std::ofstream(dir + "/zzzz.bag", std::ios::binary) << bytes;
    }
    e = errorOf([&] { importRosbag(dir + "/zzzz.bag", roundTripParams(), dir + "/x.rawlog"); });
    EXPECT_EQ(e.rfind(dir + "/zzzz.bag: ", 0), 0u) << e;
    EXPECT_NE(e.find("zzzz"), std::string::npos) << e;
    EXPECT_TRUE(oneLine(e)) << e;
    std::cout << "[ ros1 unknown compression ] " << e << "\n";

    // PointCloud2 without x/y/z.
    {
        rosbag::Bag b(dir + "/noxyz.bag", rosbag::bagmode::Write);
        b.write("/points", rosTime(5.0), cloud(5.0, 10, "lidar", false));
        b.close();
    }
    e = errorOf([&] { importRosbag(dir + "/noxyz.bag", {}, dir + "/x.rawlog"); });
    EXPECT_NE(e.find(dir + "/noxyz.bag: topic '/points': scan at"), std::string::npos) << e;
    EXPECT_NE(e.find("without x, y and z"), std::string::npos) << e;
    EXPECT_TRUE(oneLine(e));

    // Non-monotonic stamps: with stamp_source = header the repeated/backward scan is skipped and
    // counted; auto stamps the topic with the record time instead (2 of 5 do not increase).
    {
        rosbag::Bag b(dir + "/backwards.bag", rosbag::bagmode::Write);
        int k = 0;  // bag (receive) time increases, header.stamp does not
        for (double t : {5.0, 5.1, 5.05, 5.2, 5.2})
            b.write("/points", rosTime(10 + k++), cloud(t, 10, "lidar"));
        b.close();
    }
    RosbagParams hp;
    hp.stamp_source = "header";
    const auto r = importRosbag(dir + "/backwards.bag", hp, dir + "/back.rawlog");
    EXPECT_EQ(r.scans, 3u);
    ASSERT_EQ(r.non_monotonic.size(), 1u);
    EXPECT_EQ(r.non_monotonic[0].first, "/points");
    EXPECT_EQ(r.non_monotonic[0].second, 2u);
    const auto ra = importRosbag(dir + "/backwards.bag", {}, dir + "/back.rawlog");
    EXPECT_EQ(ra.scans, 5u);
    EXPECT_TRUE(ra.non_monotonic.empty());
    ASSERT_EQ(ra.stamps.size(), 1u);
    EXPECT_EQ(ra.stamps[0].reason, "header.stamp does not increase on 2 of 5 messages");
}

#endif  // SUPERLOC_HAVE_ROS1
