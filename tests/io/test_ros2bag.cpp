// ROS 2 bags (.db3 and MCAP) built here from the real kitti00-mini scans by the test writers
// (tests/support/superloc_testing/bag_writers.h): the same scans through the KITTI importer, the
// shared ROS 1 bag, .db3 and MCAP give identical points and times; a round trip of every
// supported message type through each format; bad input; deskew of a scan with known motion.
#include <superloc/core/se3.h>
#include <superloc/features/deskew.h>
#include <superloc/io/importers.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/rosbag.h>
#include <superloc/io/tum.h>
#include <superloc_testing/bag_writers.h>
#include <superloc_testing/bag_content.h>
#include <superloc_testing/testing.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>

#include "../../modules/io/src/bag/bag_source.h"

namespace {

using namespace superloc;
using superloc::testing::bag::kT_base_imu;
using superloc::testing::bag::kT_base_lidar;
using superloc::testing::bag::symCov;
using namespace superloc::io;
namespace bw = superloc::testing::bag;

std::vector<RawlogItem> readAll(const std::string& path) {
    RawlogParams rp;
    rp.scan_period = 0;  // only what the rawlog carries
    RawlogReader r(path, rp);
    std::vector<RawlogItem> items;
    RawlogItem it;
    while (r.next(it)) items.push_back(it);
    return items;
}

std::vector<const Scan*> scansOf(const std::vector<RawlogItem>& items) {
    std::vector<const Scan*> out;
    for (const auto& it : items)
        if (it.kind == RawlogItem::Kind::Lidar) out.push_back(&it.scan());
    return out;
}

using superloc::testing::errorOf;

bool oneLine(const std::string& e) { return !e.empty() && e.find('\n') == std::string::npos; }

std::vector<uint8_t> slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

void spit(const std::string& path, const std::vector<uint8_t>& b, size_t n) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), std::streamsize(n));
}

// --- fixtures from the real kitti00-mini scans ----------------------------------------------

/// KITTI time t as a ROS stamp 1e9 + t (the shared bag's convention: ROS time 0 means unset).
bw::Time rosStamp(double t) {
    const double whole = std::floor(t);
    bw::Time s;
    s.sec = int32_t(1000000000 + int64_t(whole));
    s.nsec = uint32_t(std::llround((t - whole) * 1e9));
    if (s.nsec >= 1000000000u) ++s.sec, s.nsec -= 1000000000u;
    return s;
}

struct KittiScan {
    double t;
    std::vector<uint8_t> bin;  ///< float32 x y z reflectance, as in the file
};

std::vector<KittiScan> kittiScans(size_t n) {
    const auto dir = superloc::testing::sharedData("kitti00-mini");
    std::ifstream times(dir + "/times.txt");
    std::vector<KittiScan> out;
    double t;
    for (size_t i = 0; i < n && times >> t; ++i) {
        char name[64];
        std::snprintf(name, sizeof(name), "/velodyne/%06zu.bin", i);
        out.push_back({t, slurp(dir + name)});
    }
    return out;
}

bw::Pose toPose(const SE3d& T) {
    const Eigen::Quaterniond q(T.rotation());
    return {
        T.translation().x(), T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w()};
}

bw::Field field(const std::string& name, uint32_t offset, uint8_t type) {
    return {name, offset, type, 1};
}

/// The shared bag's extrinsic: base_link -> velodyne, t = (0.27, 0, 1.73) m, yaw 1.5 deg.
const SE3d kT_base_velodyne = makePoseRPY(0.27, 0, 1.73, 0, 0, 1.5 * M_PI / 180);

/// The kitti00-mini scans as the shared ROS 1 bag holds them: /velodyne_points (x y z
/// intensity float32, the .bin bytes as they are), /tf_static, /ground_truth (Odometry of
/// base_link, covariance diag 1e-4 m^2, 1e-6 rad^2).
std::vector<bw::Message> kittiBagMessages() {
    const auto scans = kittiScans(16);
    const auto gt = loadTum(superloc::testing::sharedData("kitti00-mini/gt_velodyne_tum.txt"));
    std::vector<bw::Message> msgs;
    bw::Transform x{rosStamp(scans[0].t), "base_link", "velodyne", toPose(kT_base_velodyne)};
    msgs.push_back({"/tf_static", "tf2_msgs/msg/TFMessage", x.stamp.ns(), bw::cdr({x})});
    for (size_t i = 0; i < scans.size(); ++i) {
        bw::Cloud c;
        c.stamp = rosStamp(scans[i].t);
        c.frame = "velodyne";
        c.width = uint32_t(scans[i].bin.size() / 16);
        c.point_step = 16;
        c.row_step = c.width * 16;
        c.fields = {field("x", 0, 7), field("y", 4, 7), field("z", 8, 7),
                    field("intensity", 12, 7)};
        c.data = scans[i].bin;
        msgs.push_back(
            {"/velodyne_points", "sensor_msgs/msg/PointCloud2", c.stamp.ns(), bw::cdr(c)});
        bw::Odometry o;
        o.stamp = c.stamp;
        o.frame = "map";
        o.child = "base_link";
        o.pose = toPose(gt[i].pose * kT_base_velodyne.inverse());
        for (int k = 0; k < 6; ++k) o.covariance[size_t(k * 7)] = k < 3 ? 1e-4 : 1e-6;
        msgs.push_back({"/ground_truth", "nav_msgs/msg/Odometry", c.stamp.ns(), bw::cdr(o)});
    }
    return msgs;
}

/// Per-point time of a real scan: the azimuth's share of a 0.1 s sweep, in ns (uint32), as an
/// Ouster driver writes its `t` field.
uint32_t azimuthTimeNs(float x, float y) {
    const double frac = (std::atan2(double(y), double(x)) + M_PI) / (2 * M_PI);
    return uint32_t(std::min(frac, 1.0 - 1e-9) * 1e8);
}

const double kT0 = 1700000000.25;

/// Round-trip fixture: 2 real KITTI scans with a per-point `t` (uint32 ns, relative to the
/// stamp) on /points, 20 IMU samples, Odometry with a full 6x6 covariance on /odom,
/// PoseStamped ground truth on /gt, /tf_static with base_link -> lidar and base_link -> imu_link.
std::vector<bw::Message> roundTripMessages() {
    const auto scans = kittiScans(2);
    std::vector<bw::Message> msgs;
    const auto stamp = [](double t) {
        bw::Time s;
        s.sec = int32_t(std::floor(t));
        s.nsec = uint32_t(std::llround((t - std::floor(t)) * 1e9));
        return s;
    };
    bw::Transform a{stamp(kT0), "base_link", "lidar", toPose(kT_base_lidar)};
    bw::Transform b{stamp(kT0), "base_link", "imu_link", toPose(kT_base_imu)};
    msgs.push_back({"/tf_static", "tf2_msgs/msg/TFMessage", stamp(kT0).ns(), bw::cdr({a, b})});
    for (int k = 0; k < 20; ++k) {
        bw::Imu m;
        m.stamp = stamp(kT0 + 0.01 * k);
        m.frame = "imu_link";
        m.acc = {0.1 * k, -0.2, 9.81};
        m.gyro = {0.01, -0.02 * k, 0.5};
        msgs.push_back({"/imu", "sensor_msgs/msg/Imu", m.stamp.ns(), bw::cdr(m)});
    }
    for (int k = 0; k < 2; ++k) {
        const double t = kT0 + 0.1 * k;
        bw::Cloud c;
        c.stamp = stamp(t);
        c.frame = "lidar";
        const size_t n = scans[size_t(k)].bin.size() / 16;
        c.width = uint32_t(n);
        c.point_step = 20;
        c.row_step = c.width * 20;
        c.fields = {field("x", 0, 7), field("y", 4, 7), field("z", 8, 7), field("intensity", 12, 7),
                    field("t", 16, 6)};
        c.data.resize(n * 20);
        for (size_t i = 0; i < n; ++i) {
            float v[4];
            std::memcpy(v, &scans[size_t(k)].bin[i * 16], 16);
            const uint32_t t_ns = azimuthTimeNs(v[0], v[1]);
            std::memcpy(&c.data[i * 20], v, 16);
            std::memcpy(&c.data[i * 20 + 16], &t_ns, 4);
        }
        msgs.push_back({"/points", "sensor_msgs/msg/PointCloud2", c.stamp.ns(), bw::cdr(c)});
        bw::Odometry o;
        o.stamp = c.stamp;
        o.frame = "odom";
        o.child = "base_link";
        o.pose = toPose(makePoseRPY(k * 0.5, 0.1 * k, 0, 0, 0, 0.1 * k));
        for (size_t i = 0; i < 36; ++i) o.covariance[i] = symCov(i, k);
        msgs.push_back({"/odom", "nav_msgs/msg/Odometry", o.stamp.ns(), bw::cdr(o)});
        bw::PoseStamped g;
        g.stamp = c.stamp;
        g.frame = "map";
        g.pose = toPose(makePoseRPY(10 + k * 0.5, 5, 1, 0.01, 0, 0.2 + 0.1 * k));
        msgs.push_back({"/gt", "geometry_msgs/msg/PoseStamped", g.stamp.ns(), bw::cdr(g)});
    }
    // Recorders write in receive order; sort by bag time like a recording.
    std::stable_sort(msgs.begin(), msgs.end(), [](const bw::Message& x, const bw::Message& y) {
        return x.time_ns < y.time_ns;
    });
    return msgs;
}

RosbagParams roundTripParams() {
    RosbagParams p;
    p.lidar_topic = "/points";
    p.odom_alt_topic = "/odom";
    p.gt_topic = "/gt";
    p.gt_child_frame = "base_link";
    return p;  // body frame: the IMU's (imu_link)
}

/// The round-trip fixture in every format: db3, MCAP with uncompressed / zstd / lz4 chunks
/// (small chunks, so that scans span several), MCAP without chunks.
std::vector<std::string> writeRoundTripBags(const std::string& dir) {
    const auto msgs = roundTripMessages();
    std::vector<std::string> files{dir + "/rt.db3"};
    bw::writeDb3(files[0], msgs);
    for (const std::string c : {"", "zstd", "lz4", "nochunks"}) {
        files.push_back(dir + "/rt-" + (c.empty() ? "none" : c) + ".mcap");
        bw::McapOptions o;
        o.compression = c;
        o.chunk_bytes = 1 << 19;
        bw::writeMcap(files.back(), msgs, o);
    }
    return files;
}

}  // namespace

TEST(Ros2Bag, KittiScansSameThroughKittiRos1Db3AndMcap) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("ros2bag_kitti");
    const auto msgs = kittiBagMessages();
    bw::writeDb3(dir + "/k.db3", msgs);
    bw::writeMcap(dir + "/k.mcap", msgs);  // zstd chunks of 1 MiB
    RosbagParams p;
    p.gt_topic = "/ground_truth";
    const auto t0 = std::chrono::steady_clock::now();
    const auto rd = importRosbag(dir + "/k.db3", p, dir + "/db3.rawlog");
    const auto t1 = std::chrono::steady_clock::now();
    const auto rm = importRosbag(dir + "/k.mcap", p, dir + "/mcap.rawlog");
    const auto t2 = std::chrono::steady_clock::now();
    const auto rk =
        importKitti(superloc::testing::sharedData("kitti00-mini"), "", "", dir + "/kitti.rawlog");
    std::cout << "[ kitti db3/mcap ] import " << std::chrono::duration<double>(t1 - t0).count()
              << " s (.db3, " << std::filesystem::file_size(dir + "/k.db3") / 1e6 << " MB), "
              << std::chrono::duration<double>(t2 - t1).count() << " s (.mcap zstd, "
              << std::filesystem::file_size(dir + "/k.mcap") / 1e6 << " MB)\n";
    for (const auto* r : {&rd, &rm}) {
        EXPECT_EQ(r->scans, 16u);
        EXPECT_EQ(r->points, rk.points);
        EXPECT_EQ(r->gt_poses, 16u);
    }
    std::vector<std::pair<std::string, std::vector<RawlogItem>>> runs;
    runs.emplace_back("db3", readAll(dir + "/db3.rawlog"));
    runs.emplace_back("mcap", readAll(dir + "/mcap.rawlog"));
#ifdef SUPERLOC_HAVE_ROS1
    importRosbag(superloc::testing::sharedData("rosbag-kitti00-mini/kitti00-mini.bag"), p,
                 dir + "/ros1.rawlog");
    runs.emplace_back("ros1", readAll(dir + "/ros1.rawlog"));
#endif
    const auto kit = readAll(dir + "/kitti.rawlog");
    const auto ks = scansOf(kit);
    ASSERT_EQ(ks.size(), 16u);
    const auto db3 = scansOf(runs[0].second);
    for (const auto& [name, items] : runs) {
        const auto bs = scansOf(items);
        ASSERT_EQ(bs.size(), 16u) << name;
        double max_dt_kitti = 0, max_dt_db3 = 0;
        for (size_t i = 0; i < 16; ++i) {
            ASSERT_EQ(bs[i]->points.size(), ks[i]->points.size()) << name << " " << i;
            EXPECT_EQ(std::memcmp(bs[i]->points.data(), ks[i]->points.data(),
                                  ks[i]->points.size() * sizeof(Vec3f)),
                      0)
                << name << " " << i;
            EXPECT_EQ(bs[i]->intensity, ks[i]->intensity) << name << " " << i;
            EXPECT_TRUE(bs[i]->rel_time.empty());
            max_dt_kitti = std::max(max_dt_kitti, std::abs((bs[i]->t - 1e9) - ks[i]->t));
            max_dt_db3 = std::max(max_dt_db3, std::abs(bs[i]->t - db3[i]->t));
        }
        std::cout << "[ kitti " << name << " ] max |t - 1e9 - t_kitti| = " << max_dt_kitti
                  << " s, max |t - t_db3| = " << max_dt_db3 << " s\n";
        EXPECT_LE(max_dt_kitti, 2e-7) << name;
        if (name == "mcap") {
            EXPECT_EQ(max_dt_db3, 0.0);  // same stamps, same conversion
        }
        EXPECT_LE(max_dt_db3, 2e-7) << name;
    }
    // Ground truth: base_link poses * T_base_velodyne (tf_static) = gt_velodyne_tum.txt.
    const auto gt = loadTum(superloc::testing::sharedData("kitti00-mini/gt_velodyne_tum.txt"));
    for (const auto& [name, items] : runs) {
        size_t k = 0;
        double max_dp = 0;
        for (const auto& it : items)
            if (it.kind == RawlogItem::Kind::GroundTruth && k < gt.size())
                max_dp = std::max(max_dp, translationDistance(it.pose().pose, gt[k++].pose));
        EXPECT_EQ(k, gt.size()) << name;
        EXPECT_LT(max_dp, 1e-5) << name;
    }
}

TEST(Ros2Bag, ListsTopicsWithTheirRos2Types) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("ros2bag_list");
    for (const auto& f : writeRoundTripBags(dir)) {
        const auto topics = listRosbag(f);
        ASSERT_EQ(topics.size(), 5u) << f;
        EXPECT_EQ(topics[0].topic, "/gt");
        EXPECT_EQ(topics[0].type, "geometry_msgs/msg/PoseStamped");
        EXPECT_EQ(topics[1].topic, "/imu");
        EXPECT_EQ(topics[1].messages, 20u);
        EXPECT_EQ(topics[3].topic, "/points");
        EXPECT_EQ(topics[3].messages, 2u);
    }
}

TEST(Ros2Bag, RoundTripEveryFieldThroughDb3AndMcap) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("ros2bag_roundtrip");
    const auto files = writeRoundTripBags(dir);
    const auto scans = kittiScans(2);
    const SE3d T_imu_lidar = kT_base_imu.inverse() * kT_base_lidar;
    std::vector<std::vector<RawlogItem>> all;
    for (const auto& f : files) {
        SCOPED_TRACE(f);
        // Exact at the reader: points and per-point times as written, bit for bit.
        auto bag = detail::openBag(f);
        size_t k = 0;
        bag->forEach({"/points"}, [&](const detail::BagMessage& m) {
            Scan s;
            detail::decodePointCloud2(m.pointCloud2().cloud, {}, s);
            const auto& bin = scans[k].bin;
            EXPECT_EQ(s.size(), bin.size() / 16);
            size_t bad_p = 0, bad_t = 0;
            for (size_t i = 0; i < s.size(); ++i) {
                float v[4];
                std::memcpy(v, &bin[i * 16], 16);
                bad_p += s.points[i] != Vec3f(v[0], v[1], v[2]);
                bad_t += s.rel_time[i] != float(double(azimuthTimeNs(v[0], v[1])) * 1e-9);
            }
            EXPECT_EQ(bad_p, 0u);
            EXPECT_EQ(bad_t, 0u);
            ++k;
            return true;
        });
        EXPECT_EQ(k, 2u);

        // Through the rawlog.
        const auto r = importRosbag(f, roundTripParams(), f + ".rawlog");
        EXPECT_EQ(r.scans, 2u);
        EXPECT_EQ(r.timed_scans, 2u);
        EXPECT_EQ(r.time_field, "t");
        EXPECT_EQ(r.imu, 20u);
        EXPECT_EQ(r.odom_alt, 2u);
        EXPECT_EQ(r.gt_poses, 2u);
        EXPECT_TRUE(r.non_monotonic.empty());
        all.push_back(readAll(f + ".rawlog"));
        size_t n_scan = 0, imus = 0, odoms = 0, gts = 0;
        for (const auto& it : all.back()) {
            switch (it.kind) {
                case RawlogItem::Kind::Lidar: {
                    const Scan& s = it.scan();
                    const auto& bin = scans[n_scan].bin;
                    ASSERT_EQ(s.size(), bin.size() / 16);
                    EXPECT_NEAR(s.t, kT0 + 0.1 * n_scan, 1e-6);
                    EXPECT_TRUE(s.T_imu_lidar.isApprox(T_imu_lidar, 1e-9));
                    double max_dt = 0;
                    size_t bad_p = 0;
                    for (size_t i = 0; i < s.size(); ++i) {
                        float v[4];
                        std::memcpy(v, &bin[i * 16], 16);
                        bad_p += s.points[i] != Vec3f(v[0], v[1], v[2]);
                        max_dt = std::max(max_dt, std::abs(double(s.rel_time[i]) -
                                                           azimuthTimeNs(v[0], v[1]) * 1e-9));
                    }
                    EXPECT_EQ(bad_p, 0u);
                    EXPECT_LE(max_dt, 1.01e-7);  // the rawlog keeps MRPT's 100 ns clock
                    ++n_scan;
                    break;
                }
                case RawlogItem::Kind::Imu: {
                    superloc::testing::bag::expectImu(it.imu(), int(imus), kT0);
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
        EXPECT_EQ(n_scan, 2u);
        EXPECT_EQ(imus, 20u);
        EXPECT_EQ(odoms, 2u);
        EXPECT_EQ(gts, 2u);
    }
    // Every format gives the same rawlog content, item by item.
    for (size_t f = 1; f < all.size(); ++f) {
        ASSERT_EQ(all[f].size(), all[0].size()) << files[f];
        for (size_t i = 0; i < all[0].size(); ++i) {
            const auto &a = all[0][i], &b = all[f][i];
            ASSERT_EQ(a.kind, b.kind) << files[f] << " item " << i;
            EXPECT_EQ(a.time(), b.time()) << files[f] << " item " << i;
            if (a.kind == RawlogItem::Kind::Lidar) {
                EXPECT_EQ(a.scan().points, b.scan().points);
                EXPECT_EQ(a.scan().rel_time, b.scan().rel_time);
                EXPECT_EQ(a.scan().intensity, b.scan().intensity);
            } else if (a.kind != RawlogItem::Kind::Imu) {
                EXPECT_TRUE(a.pose().pose.matrix() == b.pose().pose.matrix());
            }
        }
    }
}

TEST(Ros2Bag, BadInputIsOneLineNamingFileAndTopic) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("ros2bag_bad");
    const auto files = writeRoundTripBags(dir);
    const std::string db3 = files[0], mcap = files[2];  // zstd chunks
    const auto expectError = [&](const std::string& file, const RosbagParams& p,
                                 const std::vector<std::string>& parts) {
        const auto e = errorOf([&] { importRosbag(file, p, dir + "/x.rawlog"); });
        EXPECT_TRUE(oneLine(e)) << file << ": <<" << e << ">>";
        EXPECT_EQ(e.rfind(file + ": ", 0), 0u) << e;
        for (const auto& part : parts) EXPECT_NE(e.find(part), std::string::npos) << e;
        return e;
    };

    // Truncated: the first half (and the first 100 bytes) of each format.
    for (const auto& f : files) {
        const auto bytes = slurp(f);
        for (size_t n : {bytes.size() / 2, size_t(100)}) {
            const std::string t =
                f + ".trunc" + std::to_string(n) + std::filesystem::path(f).extension().string();
            spit(t, bytes, n);
            expectError(t, roundTripParams(), {});
        }
    }

    // Unknown MCAP chunk compression (the records stored as they are, named "brotli").
    {
        bw::McapOptions o;
        o.compression = "brotli";
        bw::writeMcap(dir + "/brotli.mcap", roundTripMessages(), o);
        expectError(dir + "/brotli.mcap", roundTripParams(), {"unknown compression", "brotli"});
    }

    // Wrong message type on a mapped topic: declared, and in the bytes.
    for (const auto& f : {db3, mcap}) {
        auto p = roundTripParams();
        p.odom_alt_topic = "/imu";
        expectError(f, p,
                    {"topic '/imu' ([rosbag] odom_alt_topic) is sensor_msgs/msg/Imu, "
                     "expected nav_msgs/Odometry"});
    }
    auto msgs = roundTripMessages();
    for (auto& m : msgs)
        if (m.topic == "/gt") m.type = "nav_msgs/msg/Odometry";  // PoseStamped bytes
    bw::writeDb3(dir + "/lie.db3", msgs);
    bw::writeMcap(dir + "/lie.mcap", msgs);
    for (const auto& f : {dir + "/lie.db3", dir + "/lie.mcap"})
        expectError(f, roundTripParams(), {"topic '/gt': message at bag time", "CDR: "});

    // PointCloud2 without x/y/z; XCDR2 encapsulation; a JSON-encoded channel.
    msgs = roundTripMessages();
    for (auto& m : msgs)
        if (m.topic == "/points") {
            const uint8_t name[] = {2, 0, 0, 0, 'x', 0};  // CDR string "x"
            auto pos = std::search(m.data.begin(), m.data.end(), name, name + 6);
            ASSERT_NE(pos, m.data.end());
            pos[4] = 'u';  // the field "x" is now "u"
        }
    bw::writeDb3(dir + "/noxyz.db3", msgs);
    bw::writeMcap(dir + "/noxyz.mcap", msgs);
    for (const auto& f : {dir + "/noxyz.db3", dir + "/noxyz.mcap"})
        expectError(f, roundTripParams(), {"topic '/points': scan at", "without x, y and z"});
    msgs = roundTripMessages();
    for (auto& m : msgs)
        if (m.topic == "/imu") m.data[1] = 0x07;  // XCDR2 little endian
    bw::writeDb3(dir + "/xcdr2.db3", msgs);
    expectError(dir + "/xcdr2.db3", roundTripParams(), {"topic '/imu'", "not plain CDR"});

    // Non-monotonic stamps: with stamp_source = header the repeated/backward scan is skipped and
    // counted; auto stamps the topic with the receive time instead (2 of 5 do not increase).
    msgs.clear();
    const auto scan = roundTripMessages();
    const bw::Message* pc = nullptr;
    for (const auto& m : scan)
        if (m.topic == "/points") pc = &m;
    int k = 0;
    for (int32_t sec : {5, 6, 4, 7, 7}) {
        bw::Message m = *pc;
        std::memcpy(&m.data[4], &sec, 4);            // header.stamp.sec right after the CDR header
        m.time_ns = int64_t(10 + k++) * 1000000000;  // bag time increases, header.stamp does not
        msgs.push_back(m);
    }
    bw::writeDb3(dir + "/back.db3", msgs);
    bw::writeMcap(dir + "/back.mcap", msgs);
    for (const auto& f : {dir + "/back.db3", dir + "/back.mcap"}) {
        RosbagParams p;
        p.lidar_extrinsic = "0 0 0 0 0 0 1";
        p.stamp_source = "header";
        const auto r = importRosbag(f, p, dir + "/back.rawlog");
        EXPECT_EQ(r.scans, 3u) << f;
        ASSERT_EQ(r.non_monotonic.size(), 1u) << f;
        EXPECT_EQ(r.non_monotonic[0].first, "/points");
        EXPECT_EQ(r.non_monotonic[0].second, 2u);
        p.stamp_source = "auto";
        const auto ra = importRosbag(f, p, dir + "/back.rawlog");
        EXPECT_EQ(ra.scans, 5u) << f;
        EXPECT_TRUE(ra.non_monotonic.empty()) << f;
        ASSERT_EQ(ra.stamps.size(), 1u);
        EXPECT_EQ(ra.stamps[0].reason, "header.stamp does not increase on 2 of 5 messages");
    }

    // Not a bag at all, and a missing file.
    std::ofstream(dir + "/text.db3") << "hello\n";
    expectError(dir + "/text.db3", {}, {"not a bag"});
    expectError(dir + "/missing.mcap", {}, {"no such bag"});
}

// A real scan (KITTI 00 scan 0, motion-compensated: the static geometry) re-observed by a sensor
// moving at 8 m/s forward, 0.5 m/s sideways and 0.6 rad/s of yaw during its 0.1 s sweep, each
// point with its absolute time (float64 `timestamp`); imported through MCAP, read back, and
// deskewed with features::deskewPoints and the known twist.
TEST(Ros2Bag, DeskewOfAScanWithKnownMotionRecoversTheStaticGeometry) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("ros2bag_deskew");
    const auto bin = kittiScans(1)[0].bin;
    const size_t n = bin.size() / 16;
    const Vec3d v(8.0, 0.5, 0.0), w(0.0, 0.0, 0.6);
    const double period = 0.1, stamp = kT0;
    std::vector<Vec3f> truth(n);
    bw::Cloud c;
    c.stamp = {int32_t(std::floor(stamp)),
               uint32_t(std::llround((stamp - std::floor(stamp)) * 1e9))};
    c.frame = "lidar";
    c.width = uint32_t(n);
    c.point_step = 24;
    c.row_step = c.width * 24;
    c.fields = {field("x", 0, 7), field("y", 4, 7), field("z", 8, 7), field("intensity", 12, 7),
                field("timestamp", 16, 8)};
    c.data.resize(n * 24);
    double max_skew = 0;
    for (size_t i = 0; i < n; ++i) {
        float p[4];
        std::memcpy(p, &bin[i * 16], 16);
        truth[i] = Vec3f(p[0], p[1], p[2]);
        // Sweep ending at the stamp: s in [-period, 0); T_end_s = (Exp(w s), v s).
        const double s = -period + period * azimuthTimeNs(p[0], p[1]) * 1e-8;
        SE3d T_end_s = SE3d::Identity();
        T_end_s.linear() = expSO3(w * s);
        T_end_s.translation() = v * s;
        const Vec3d seen = T_end_s.inverse() * truth[i].cast<double>();
        max_skew = std::max(max_skew, (seen - truth[i].cast<double>()).norm());
        const float q[4] = {float(seen.x()), float(seen.y()), float(seen.z()), p[3]};
        const double t_abs = stamp + s;
        std::memcpy(&c.data[i * 24], q, 16);
        std::memcpy(&c.data[i * 24 + 16], &t_abs, 8);
    }
    bw::writeMcap(dir + "/moving.mcap",
                  {{"/points", "sensor_msgs/msg/PointCloud2", c.stamp.ns(), bw::cdr(c)}});
    RosbagParams p;
    p.lidar_extrinsic = "0 0 0 0 0 0 1";
    const auto r = importRosbag(dir + "/moving.mcap", p, dir + "/moving.rawlog");
    EXPECT_EQ(r.timed_scans, 1u);
    EXPECT_EQ(r.time_field, "timestamp");
    const auto items = readAll(dir + "/moving.rawlog");
    ASSERT_EQ(items.size(), 1u);
    const Scan& s = items[0].scan();
    ASSERT_EQ(s.size(), n);
    std::vector<uint32_t> idx(n);
    std::iota(idx.begin(), idx.end(), 0u);
    std::vector<Vec3f> raw_err_pts, out;
    features::deskewPoints(s.points, s.rel_time, idx,
                           features::SweepMotion::fromTwist(v, w, period), out);
    double max_before = 0, max_after = 0, sum_before = 0;
    for (size_t i = 0; i < n; ++i) {
        const double b = (s.points[i] - truth[i]).norm(), a = (out[i] - truth[i]).norm();
        max_before = std::max(max_before, b);
        sum_before += b;
        max_after = std::max(max_after, a);
    }
    std::cout << "[ deskew ] " << n << " points, distortion mean " << sum_before / n << " m, max "
              << max_before << " m; after deskew max " << max_after << " m\n";
    EXPECT_GT(max_before, 1.0);  // the motion matters
    EXPECT_LT(max_after, 2e-3);  // float points, 100 ns clock, 16-sample motion table
    EXPECT_NEAR(max_before, max_skew, 1e-3);
}
