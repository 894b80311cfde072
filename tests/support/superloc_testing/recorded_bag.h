// Test support: a bag as a robot records it, with the clock and frame faults real drivers have
// (issue 29): LiDAR header stamps left at 0, an empty frame_id, an IMU or ground truth whose
// header clock is far from the recorder's. One description (visitRecording), written as ROS 2
// messages for the .db3 / MCAP writers (ros2Messages) or as a ROS 1 bag (writeRos1Recording,
// in builds with ROS 1 support). Used by tests/io/test_bag_clocks.cpp and
// test_import_app_exe.cpp.
#pragma once

#include <superloc/core/se3.h>
#include <superloc_testing/bag_content.h>
#include <superloc_testing/bag_writers.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#ifdef SUPERLOC_HAVE_ROS1
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#endif

namespace superloc::testing::bag {

/// What the recording holds. Times: scan k happens at kRecT0 + 0.1 k s and is recorded 60 ms
/// later (driver + transport latency); IMU sample j happens at kRecT0 + 0.01 j s (j from -5 to
/// 10 * scans + 5) and is recorded 2 ms later; ground truth k at the scans' times, recorded 1 ms
/// later. /tf_static (base_link -> lidar, base_link -> imu_link: kT_base_lidar, kT_base_imu)
/// first.
struct Recording {
    size_t scans = 12;               ///< on /points, 100 points each, fields x y z intensity t
    bool lidar_stamps = true;        ///< false: every scan's header.stamp is 0 (unset)
    std::string lidar_frame = "lidar";
    bool imu = true;                 ///< /imu
    std::string imu_frame = "imu_link";
    int64_t imu_clock_offset_ns = 0;  ///< added to the IMU's header.stamp (its clock's error)
    bool gt = false;                 ///< /gt, nav_msgs/Odometry of base_link in map
    int64_t gt_clock_offset_ns = 0;  ///< added to the ground truth's header.stamp
};

constexpr int64_t kRecT0 = 1700000000LL * 1000000000LL;  ///< [ns] the first scan's time

/// Point i of scan k: x y z intensity (float32), t (uint32 ns after the stamp, 1 ms apart).
inline Cloud recordedCloud(int k, const Time& stamp, const std::string& frame, size_t n = 100) {
    Cloud c;
    c.stamp = stamp;
    c.frame = frame;
    c.width = uint32_t(n);
    c.point_step = 20;
    c.row_step = c.width * 20;
    c.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"intensity", 12, 7, 1},
                {"t", 16, 6, 1}};
    c.data.resize(n * 20);
    for (size_t i = 0; i < n; ++i) {
        const float v[4] = {float(2 + 0.1 * i), float(-1 + 0.02 * i + 0.01 * k), float(0.05 * i),
                            float(i % 100)};
        const uint32_t t = uint32_t(i * 1000000);
        std::memcpy(&c.data[i * 20], v, 16);
        std::memcpy(&c.data[i * 20 + 16], &t, 4);
    }
    return c;
}

inline Time rosTimeNs(int64_t ns) { return {int32_t(ns / 1000000000), uint32_t(ns % 1000000000)}; }

inline Pose poseOf(const SE3d& T) {
    const Eigen::Quaterniond q(T.rotation());
    return {T.translation().x(), T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w()};
}

/// Ground truth k: base_link at (0.5 k, 0, 0).
inline SE3d recordedGt(int k) { return makePoseRPY(0.5 * k, 0, 0, 0, 0, 0); }

/// Calls `visit(record_ns, topic, message)` for every message of the recording in record-time
/// order; the message is a Cloud, Imu, Odometry or std::vector<Transform> (the ROS 2 writers'
/// structs, which the ROS 1 writer converts).
template <class Visit>
void visitRecording(const Recording& r, Visit&& visit) {
    struct Entry {
        int64_t record_ns;
        int kind;  // 0 tf, 1 scan, 2 gt, 3 imu
        int k;
    };
    std::vector<Entry> all{{kRecT0 - 100000000, 0, 0}};
    for (int k = 0; k < int(r.scans); ++k) {
        all.push_back({kRecT0 + k * 100000000LL + 60000000, 1, k});
        if (r.gt) all.push_back({kRecT0 + k * 100000000LL + 1000000, 2, k});
    }
    if (r.imu)
        for (int j = -5; j <= int(r.scans) * 10 + 5; ++j)
            all.push_back({kRecT0 + j * 10000000LL + 2000000, 3, j});
    std::stable_sort(all.begin(), all.end(),
                     [](const Entry& a, const Entry& b) { return a.record_ns < b.record_ns; });
    for (const auto& e : all) {
        if (e.kind == 0) {
            const Time s = rosTimeNs(e.record_ns);
            visit(e.record_ns, "/tf_static",
                  std::vector<Transform>{{s, "base_link", "lidar", poseOf(kT_base_lidar)},
                                         {s, "base_link", "imu_link", poseOf(kT_base_imu)}});
        } else if (e.kind == 1) {
            const int64_t t = kRecT0 + e.k * 100000000LL;
            visit(e.record_ns, "/points",
                  recordedCloud(e.k, rosTimeNs(r.lidar_stamps ? t : 0), r.lidar_frame));
        } else if (e.kind == 2) {
            Odometry o;
            o.stamp = rosTimeNs(kRecT0 + e.k * 100000000LL + r.gt_clock_offset_ns);
            o.frame = "map";
            o.child = "base_link";
            o.pose = poseOf(recordedGt(e.k));
            visit(e.record_ns, "/gt", o);
        } else {
            Imu i;
            i.stamp = rosTimeNs(kRecT0 + e.k * 10000000LL + r.imu_clock_offset_ns);
            i.frame = r.imu_frame;
            i.acc = {0, 0, 9.81};
            i.gyro = {0, 0, 0.1};
            visit(e.record_ns, "/imu", i);
        }
    }
}

inline const char* ros2Type(const Cloud&) { return "sensor_msgs/msg/PointCloud2"; }
inline const char* ros2Type(const Imu&) { return "sensor_msgs/msg/Imu"; }
inline const char* ros2Type(const Odometry&) { return "nav_msgs/msg/Odometry"; }
inline const char* ros2Type(const std::vector<Transform>&) { return "tf2_msgs/msg/TFMessage"; }

/// The recording as ROS 2 messages (CDR), for writeDb3 / writeMcap.
inline std::vector<Message> ros2Messages(const Recording& r) {
    std::vector<Message> out;
    visitRecording(r, [&](int64_t ns, const char* topic, const auto& msg) {
        out.push_back({topic, ros2Type(msg), ns, cdr(msg)});
    });
    return out;
}

#ifdef SUPERLOC_HAVE_ROS1
namespace ros1 {

inline ros::Time time(const Time& t) { return ros::Time(uint32_t(t.sec), t.nsec); }

inline std_msgs::Header header(const Time& t, const std::string& frame) {
    std_msgs::Header h;
    h.stamp = time(t);
    h.frame_id = frame;
    return h;
}

inline sensor_msgs::PointCloud2 convert(const Cloud& c) {
    sensor_msgs::PointCloud2 pc;
    pc.header = header(c.stamp, c.frame);
    pc.height = c.height;
    pc.width = c.width;
    pc.point_step = c.point_step;
    pc.row_step = c.row_step;
    pc.is_bigendian = c.is_bigendian;
    pc.is_dense = c.is_dense;
    pc.data = c.data;
    for (const auto& f : c.fields) {
        sensor_msgs::PointField p;
        p.name = f.name;
        p.offset = f.offset;
        p.datatype = f.datatype;
        p.count = f.count;
        pc.fields.push_back(p);
    }
    return pc;
}

inline sensor_msgs::Imu convert(const Imu& m) {
    sensor_msgs::Imu i;
    i.header = header(m.stamp, m.frame);
    i.angular_velocity.x = m.gyro[0], i.angular_velocity.y = m.gyro[1], i.angular_velocity.z = m.gyro[2];
    i.linear_acceleration.x = m.acc[0], i.linear_acceleration.y = m.acc[1];
    i.linear_acceleration.z = m.acc[2];
    return i;
}

inline nav_msgs::Odometry convert(const Odometry& m) {
    nav_msgs::Odometry o;
    o.header = header(m.stamp, m.frame);
    o.child_frame_id = m.child;
    auto& p = o.pose.pose;
    p.position.x = m.pose.x, p.position.y = m.pose.y, p.position.z = m.pose.z;
    p.orientation.x = m.pose.qx, p.orientation.y = m.pose.qy, p.orientation.z = m.pose.qz;
    p.orientation.w = m.pose.qw;
    std::copy(m.covariance.begin(), m.covariance.end(), o.pose.covariance.begin());
    return o;
}

inline tf2_msgs::TFMessage convert(const std::vector<Transform>& tf) {
    tf2_msgs::TFMessage out;
    for (const auto& t : tf) {
        geometry_msgs::TransformStamped x;
        x.header = header(t.stamp, t.parent);
        x.child_frame_id = t.child;
        x.transform.translation.x = t.T.x, x.transform.translation.y = t.T.y;
        x.transform.translation.z = t.T.z;
        x.transform.rotation.x = t.T.qx, x.transform.rotation.y = t.T.qy;
        x.transform.rotation.z = t.T.qz, x.transform.rotation.w = t.T.qw;
        out.transforms.push_back(x);
    }
    return out;
}

}  // namespace ros1

/// The recording as a ROS 1 bag, written by rosbag_storage (record time = the bag's message time).
inline void writeRos1Recording(const std::string& path, const Recording& r) {
    rosbag::Bag b(path, rosbag::bagmode::Write);
    visitRecording(r, [&](int64_t ns, const char* topic, const auto& msg) {
        b.write(topic, ros1::time(rosTimeNs(ns)), ros1::convert(msg));
    });
    b.close();
}
#endif

}  // namespace superloc::testing::bag
