// Seeds of the bag fuzz targets (scripts/fuzz.sh): small bags cut from the real kitti00-mini
// scans (40 points of each of 2 scans, with a per-point `t` field) plus IMU, Odometry (with
// covariance), PoseStamped and /tf_static messages, written as ROS 2 .db3 (512-byte pages),
// MCAP (uncompressed, zstd and lz4 chunks, no chunks), ROS 1 .bag (when the build has ROS 1)
// and as bare CDR messages for the cdr target (first byte = message kind).
//   superloc-fuzz-bag-seeds DATA_DIR OUT_DIR  ->  OUT_DIR/{cdr,db3,mcap,ros1}/seed-*
#include <superloc_testing/bag_writers.h>

#ifdef SUPERLOC_HAVE_ROS1
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#endif

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace bw = superloc::testing::bag;

namespace {

constexpr size_t kPoints = 40;  ///< points per scan (ROS 1 seeds: 16, its chunks are larger)

std::vector<uint8_t> slurp(const std::string& path, size_t n) {
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> b(n);
    in.read(reinterpret_cast<char*>(b.data()), std::streamsize(n));
    b.resize(size_t(in.gcount()));
    return b;
}

void spit(const std::string& path, const std::vector<uint8_t>& b) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

bw::Time stamp(int k) { return {1317000000 + k / 10, uint32_t((k % 10) * 100000000)}; }

std::vector<bw::Message> messages(const std::string& data) {
    std::vector<bw::Message> msgs;
    bw::Transform x{stamp(0), "base_link", "velodyne", {0.27, 0, 1.73, 0, 0, 0.0131, 0.9999}};
    bw::Transform y{stamp(0), "base_link", "imu_link", {-0.1, 0, 0.4, 0, 0, 0, 1}};
    msgs.push_back({"/tf_static", "tf2_msgs/msg/TFMessage", stamp(0).ns(), bw::cdr({x, y})});
    for (int k = 0; k < 2; ++k) {
        char name[64];
        std::snprintf(name, sizeof(name), "/kitti00-mini/velodyne/%06d.bin", k);
        const auto bin = slurp(data + name, kPoints * 16);
        bw::Cloud c;
        c.stamp = stamp(k);
        c.frame = "velodyne";
        c.width = uint32_t(bin.size() / 16);
        c.point_step = 20;
        c.row_step = c.width * 20;
        c.fields = {{"x", 0, 7, 1},
                    {"y", 4, 7, 1},
                    {"z", 8, 7, 1},
                    {"intensity", 12, 7, 1},
                    {"t", 16, 6, 1}};
        for (size_t i = 0; i < c.width; ++i) {
            c.data.insert(c.data.end(), bin.begin() + long(i * 16),
                          bin.begin() + long(i * 16 + 16));
            const uint32_t t = uint32_t(i * 2500000);
            c.data.insert(c.data.end(), reinterpret_cast<const uint8_t*>(&t),
                          reinterpret_cast<const uint8_t*>(&t) + 4);
        }
        msgs.push_back({"/points", "sensor_msgs/msg/PointCloud2", c.stamp.ns(), bw::cdr(c)});
        for (int j = 0; j < 2; ++j) {
            bw::Imu m{stamp(k), "imu_link", {0.01, -0.02, 0.5}, {0.1 * j, -0.2, 9.81}};
            m.stamp.nsec += uint32_t(j * 50000000);
            msgs.push_back({"/imu", "sensor_msgs/msg/Imu", m.stamp.ns(), bw::cdr(m)});
        }
        bw::Odometry o{stamp(k), "odom", "base_link", {0.5 * k, 0, 0, 0, 0, 0, 1}, {}};
        for (int i = 0; i < 36; ++i) o.covariance[size_t(i)] = i % 7 ? 1e-5 : 1e-3;
        msgs.push_back({"/odom", "nav_msgs/msg/Odometry", o.stamp.ns(), bw::cdr(o)});
        bw::PoseStamped g{stamp(k), "map", {10 + 0.5 * k, 5, 1, 0, 0, 0, 1}};
        msgs.push_back({"/gt", "geometry_msgs/msg/PoseStamped", g.stamp.ns(), bw::cdr(g)});
    }
    return msgs;
}

#ifdef SUPERLOC_HAVE_ROS1
/// The same messages through ROS 1's own writer (rosbag_storage), decoded from the CDR seeds'
/// inputs again: simplest is to rebuild them with the ROS 1 message types.
void writeRos1(const std::string& path, const std::string& data, uint32_t compression) {
    rosbag::Bag b(path, rosbag::bagmode::Write);
    b.setCompression(rosbag::compression::CompressionType(compression));
    const auto t = [](int k, int j = 0) {
        ros::Time r;
        r.sec = 1317000000 + k / 10;
        r.nsec = uint32_t((k % 10) * 100000000 + j * 50000000);
        return r;
    };
    tf2_msgs::TFMessage tf;
    tf.transforms.resize(1);
    tf.transforms[0].header.stamp = t(0);
    tf.transforms[0].header.frame_id = "base_link";
    tf.transforms[0].child_frame_id = "velodyne";
    tf.transforms[0].transform.translation.x = 0.27;
    tf.transforms[0].transform.rotation.w = 1;
    b.write("/tf_static", t(0), tf);
    for (int k = 0; k < 2; ++k) {
        char name[64];
        std::snprintf(name, sizeof(name), "/kitti00-mini/velodyne/%06d.bin", k);
        sensor_msgs::PointCloud2 pc;
        pc.header.stamp = t(k);
        pc.header.frame_id = "velodyne";
        pc.data = slurp(data + name, 16 * 16);
        pc.height = 1;
        pc.width = uint32_t(pc.data.size() / 16);
        pc.point_step = 16;
        pc.row_step = pc.width * 16;
        for (const char* f : {"x", "y", "z", "intensity"}) {
            sensor_msgs::PointField pf;
            pf.name = f;
            pf.offset = uint32_t(pc.fields.size() * 4);
            pf.datatype = 7;
            pf.count = 1;
            pc.fields.push_back(pf);
        }
        b.write("/velodyne_points", t(k), pc);
        sensor_msgs::Imu imu;
        imu.header.stamp = t(k);
        imu.header.frame_id = "velodyne";
        imu.linear_acceleration.z = 9.81;
        b.write("/imu", t(k), imu);
        nav_msgs::Odometry o;
        o.header.stamp = t(k);
        o.header.frame_id = "odom";
        o.child_frame_id = "base_link";
        o.pose.pose.orientation.w = 1;
        o.pose.covariance[0] = 1e-3;
        b.write("/odom", t(k), o);
        geometry_msgs::PoseStamped g;
        g.header = o.header;
        g.pose.orientation.w = 1;
        b.write("/gt", t(k), g);
    }
    b.close();
}
#endif

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: superloc-fuzz-bag-seeds DATA_DIR OUT_DIR\n";
        return 2;
    }
    const std::string data = argv[1], out = argv[2];
    for (const char* d : {"cdr", "db3", "mcap", "ros1"})
        std::filesystem::create_directories(out + "/" + d);
    const auto msgs = messages(data);
    const std::map<std::string, uint8_t> kind{{"sensor_msgs/msg/PointCloud2", 0},
                                              {"sensor_msgs/msg/Imu", 1},
                                              {"nav_msgs/msg/Odometry", 2},
                                              {"geometry_msgs/msg/PoseStamped", 3},
                                              {"tf2_msgs/msg/TFMessage", 4}};
    std::map<uint8_t, int> seen;
    for (const auto& m : msgs) {
        const uint8_t k = kind.at(m.type);
        if (seen[k]++) continue;
        std::vector<uint8_t> b{k};
        b.insert(b.end(), m.data.begin(), m.data.end());
        spit(out + "/cdr/seed-" + std::to_string(int(k)) + ".cdr", b);
    }
    bw::writeDb3(out + "/db3/seed-kitti.db3", msgs, 512);
    for (const std::string c : {"", "zstd", "lz4", "nochunks"}) {
        bw::McapOptions o;
        o.compression = c;
        o.chunk_bytes = 2048;
        o.crc = false;  // CRC 0 = not given: mutations inside chunks are not all refused at once
        bw::writeMcap(out + "/mcap/seed-kitti-" + (c.empty() ? "none" : c) + ".mcap", msgs, o);
    }
#ifdef SUPERLOC_HAVE_ROS1
    writeRos1(out + "/ros1/seed-kitti.bag", data, 0);
    writeRos1(out + "/ros1/seed-kitti-lz4.bag", data, 2);
#endif
    for (const char* d : {"cdr", "db3", "mcap", "ros1"})
        std::cout << "seeds " << d << ": "
                  << std::distance(std::filesystem::directory_iterator(out + "/" + d),
                                   std::filesystem::directory_iterator{})
                  << "\n";
    return 0;
}
