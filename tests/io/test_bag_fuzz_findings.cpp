// Regression tests for what the bag fuzz targets found (doc/notes/fuzzing.md), and the
// corrupted-file sweep of the other readers applied to bags: random truncations and byte flips
// of a small .db3 and MCAP never crash; each loads or throws one line naming the file.
#include <superloc/io/rosbag.h>
#include <superloc_testing/bag_writers.h>
#include <superloc_testing/testing.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <random>

#include "../../modules/io/src/bag/bag_source.h"

namespace {

using namespace superloc;
namespace bw = superloc::testing::bag;

using superloc::testing::errorOf;

std::vector<bw::Message> smallBag() {
    std::vector<bw::Message> msgs;
    bw::Transform x{{100, 0}, "base_link", "lidar", {0.1, 0, 0.5, 0, 0, 0, 1}};
    msgs.push_back({"/tf_static", "tf2_msgs/msg/TFMessage", x.stamp.ns(), bw::cdr({x})});
    for (int k = 0; k < 3; ++k) {
        bw::Cloud c;
        c.stamp = {100 + k, 0};
        c.frame = "lidar";
        c.width = 8;
        c.point_step = 16;
        c.row_step = 128;
        c.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"t", 12, 7, 1}};
        c.data.resize(128);
        for (int i = 0; i < 8; ++i) {
            const float v[4] = {1.f + i, 2.f - i, 0.5f, 0.01f * i};
            std::memcpy(&c.data[size_t(i) * 16], v, 16);
        }
        msgs.push_back({"/points", "sensor_msgs/msg/PointCloud2", c.stamp.ns(), bw::cdr(c)});
        bw::Odometry o{c.stamp, "odom", "base_link", {0.1 * k, 0, 0, 0, 0, 0, 1}, {}};
        msgs.push_back({"/odom", "nav_msgs/msg/Odometry", o.stamp.ns(), bw::cdr(o)});
    }
    return msgs;
}

}  // namespace

// fuzz_cdr: a PointCloud2 of width 0 and height 4e9 looped over 4e9 empty rows (a 14 s
// timeout); it is now an empty scan at once.
TEST(BagFuzzFindings, PointCloud2WithNoPointsButHugeHeightReturnsAtOnce) {
    io::detail::PointCloud2View v;
    v.height = 4000000000u;
    v.width = 0;
    v.point_step = 12;
    v.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}};
    Scan s;
    const auto t0 = std::chrono::steady_clock::now();
    io::detail::decodePointCloud2(v, {}, s);
    EXPECT_TRUE(s.empty());
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.1);
}

// fuzz_ros1 / fuzz_mcap: rosbag_storage allocated whatever a record header length said (2-4 GB);
// the file's records are now checked against its size before rosbag_storage opens it.
TEST(BagFuzzFindings, Ros1BagWithAHugeHeaderLengthIsRefusedBeforeRosbagStorage) {
    const auto dir = superloc::testing::freshDir("bag_fuzz_ros1");
    std::string bytes = "#ROSBAG V2.0\n";
    const uint32_t huge = 0x80000000u;
    bytes.append(reinterpret_cast<const char*>(&huge), 4);
    bytes.append(64, 'x');
    std::ofstream(dir + "/huge.bag", std::ios::binary) << bytes;
    const auto e = errorOf([&] { io::listRosbag(dir + "/huge.bag"); });
    EXPECT_EQ(e, dir +
                     "/huge.bag: corrupt ROS 1 bag: record at byte 13: header length 2147483648 "
                     "runs past the end");
}

// fuzz_ros1, first seed under ASan: TFMessage decoding iterated the transforms of a message it
// had already freed. The input is kept in tests/fuzz/regressions/ and replayed here like the
// fuzz target does it (list, then import with the odometry topics mapped): it imports or fails
// with one line naming the file, and under ASan (scripts/test-sanitize.sh) any use after free
// fails the test.
TEST(BagFuzzFindings, Ros1TfMessageOfAFreedMessageIsNotRead) {
#ifndef SUPERLOC_HAVE_ROS1
    GTEST_SKIP() << "built without ROS 1 bag support";
#else
    const std::string bag = superloc::testing::sourcePath("tests/fuzz/regressions/ros1-tfmessage-freed-vector.bag");
    const std::string out = superloc::testing::freshDir("bag_fuzz_ros1_tf") + "/out.rawlog";
    const auto e = errorOf([&] {
        io::RosbagParams p;
        for (const auto& t : io::listRosbag(bag))
            if (t.type.find("Odometry") != std::string::npos && p.odom_alt_topic == "none") p.odom_alt_topic = t.topic;
        io::importRosbag(bag, p, out);
    });
    if (!e.empty()) {
        EXPECT_EQ(e.rfind(bag + ": ", 0), 0u) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    }
#endif
}

// fuzz_db3: SQLite's error text quoted a malformed schema across lines; errors are one line.
// Plus a sweep of random corruptions of a .db3 and of MCAP files (fixed seeds).
TEST(BagFuzzFindings, CorruptedBagsLoadOrThrowOneLine) {
    const auto dir = superloc::testing::freshDir("bag_fuzz_sweep");
    const auto msgs = smallBag();
    bw::writeDb3(dir + "/s.db3", msgs, 512);
    bw::McapOptions o;
    o.chunk_bytes = 256;
    o.crc = false;
    bw::writeMcap(dir + "/s.mcap", msgs, o);
    o.compression = "lz4";
    bw::writeMcap(dir + "/s-lz4.mcap", msgs, o);
    std::mt19937 rng(13);
    size_t loaded = 0, refused = 0;
    for (const std::string f : {"s.db3", "s.mcap", "s-lz4.mcap"}) {
        std::ifstream in(dir + "/" + f, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), {});
        for (int k = 0; k < 60; ++k) {
            std::string m = bytes;
            std::uniform_int_distribution<size_t> pos(0, m.size() - 1);
            if (k % 2 == 0)
                m.resize(pos(rng));
            else
                for (int i = 0; i < 8; ++i) m[pos(rng)] = char(rng());
            const std::string path = dir + "/m-" + std::to_string(k) + "-" + f;
            std::ofstream(path, std::ios::binary) << m;
            io::RosbagParams p;
            p.odom_alt_topic = "/odom";
            const auto e = errorOf([&] { io::importRosbag(path, p, dir + "/x.rawlog"); });
            if (e.empty()) {
                ++loaded;
                continue;
            }
            ++refused;
            EXPECT_EQ(e.find('\n'), std::string::npos) << e;
            EXPECT_EQ(e.rfind(path + ": ", 0), 0u) << e;
        }
    }
    std::cout << "[ bag sweep ] " << loaded << " loaded, " << refused << " refused in one line\n";
}

// fuzz_cdr / fuzz_mcap: names read from the file (a PointCloud2 field, an MCAP chunk's
// compression) went into error messages with their line breaks; they are escaped now.
TEST(BagFuzzFindings, NamesFromTheFileCannotBreakTheErrorLine) {
    io::detail::PointCloud2View v;
    v.height = 1;
    v.width = 1;
    v.point_step = 12;
    v.data_size = 12;
    const uint8_t data[12] = {};
    v.data = data;
    v.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"t\nx", 0, 42, 1}};
    Scan s;
    const auto e1 = errorOf([&] { io::detail::decodePointCloud2(v, {}, s); });
    EXPECT_EQ(e1, "PointCloud2 field 't\\x0ax' has unknown datatype 42");
    const auto dir = superloc::testing::freshDir("bag_fuzz_names");
    bw::McapOptions o;
    o.compression = "zstd\nor not";
    bw::writeMcap(dir + "/c.mcap", smallBag(), o);
    const auto e2 = errorOf([&] { io::listRosbag(dir + "/c.mcap"); });
    EXPECT_EQ(e2.find('\n'), std::string::npos) << e2;
    EXPECT_NE(e2.find("compression 'zstd\\x0aor not'): unknown compression"), std::string::npos)
        << e2;
}
