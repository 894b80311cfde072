// Test support: a bag as a robot records it, with the clock and frame faults real drivers have
// (issue 29): LiDAR header stamps left at 0, an empty frame_id, an IMU or ground truth whose
// header clock is far from the recorder's. One description (recording()), written as ROS 2
// messages for the .db3 / MCAP writers (ros2Messages) or as a ROS 1 bag (writeRos1Recording,
// builds with ROS 1 support). Used by tests/io/test_rosbag.cpp, test_ros2bag.cpp and
// test_import_app_exe.cpp.
#pragma once

#include <superloc/core/se3.h>
#include <superloc_testing/bag_content.h>
#include <superloc_testing/bag_writers.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <tuple>
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

/// One message of a recording, before serialization.
struct Recorded {
    enum class Kind { Tf, Cloud, Imu, Gt } kind;
    std::string topic;
    int64_t record_ns = 0, stamp_ns = 0;  ///< record time; header.stamp (0 = unset)
    std::string frame;
    int k = 0;  ///< scan / sample index
};

/// Point i of scan k: x y z intensity (float32), t (uint32 ns after the stamp, 1 ms apart).
inline std::vector<uint8_t> recordedCloudBytes(int k, size_t n = 100) {
    std::vector<uint8_t> d(n * 20);
    for (size_t i = 0; i < n; ++i) {
        const float v[4] = {float(2 + 0.1 * i), float(-1 + 0.02 * i + 0.01 * k), float(0.05 * i),
                            float(i % 100)};
        const uint32_t t = uint32_t(i * 1000000);
        std::memcpy(&d[i * 20], v, 16);
        std::memcpy(&d[i * 20 + 16], &t, 4);
    }
    return d;
}

/// The recording's messages in record-time order.
inline std::vector<Recorded> recording(const Recording& r) {
    using K = Recorded::Kind;
    std::vector<Recorded> out{{K::Tf, "/tf_static", kRecT0 - 100000000, kRecT0 - 100000000, "", 0}};
    for (int k = 0; k < int(r.scans); ++k) {
        const int64_t t = kRecT0 + k * 100000000LL;
        out.push_back({K::Cloud, "/points", t + 60000000, r.lidar_stamps ? t : 0, r.lidar_frame, k});
        if (r.gt) out.push_back({K::Gt, "/gt", t + 1000000, t + r.gt_clock_offset_ns, "map", k});
    }
    if (r.imu)
        for (int j = -5; j <= int(r.scans) * 10 + 5; ++j) {
            const int64_t t = kRecT0 + j * 10000000LL;
            out.push_back({K::Imu, "/imu", t + 2000000, t + r.imu_clock_offset_ns, r.imu_frame, j});
        }
    std::stable_sort(out.begin(), out.end(),
                     [](const Recorded& a, const Recorded& b) { return a.record_ns < b.record_ns; });
    return out;
}

inline Time rosTimeNs(int64_t ns) {
    return {int32_t(ns / 1000000000), uint32_t(ns % 1000000000)};
}

inline Pose poseOf(const SE3d& T) {
    const Eigen::Quaterniond q(T.rotation());
    return {T.translation().x(), T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w()};
}

/// Ground truth k: base_link at (0.5 k, 0, 0).
inline SE3d recordedGt(int k) { return makePoseRPY(0.5 * k, 0, 0, 0, 0, 0); }

/// The recording as ROS 2 messages (CDR), for writeDb3 / writeMcap.
inline std::vector<Message> ros2Messages(const Recording& r) {
    std::vector<Message> out;
    for (const auto& m : recording(r)) {
        const Time stamp = rosTimeNs(m.stamp_ns);
        switch (m.kind) {
            case Recorded::Kind::Tf: {
                const Transform a{stamp, "base_link", "lidar", poseOf(kT_base_lidar)};
                const Transform b{stamp, "base_link", "imu_link", poseOf(kT_base_imu)};
                out.push_back({m.topic, "tf2_msgs/msg/TFMessage", m.record_ns, cdr({a, b})});
                break;
            }
            case Recorded::Kind::Cloud: {
                Cloud c;
                c.stamp = stamp;
                c.frame = m.frame;
                c.data = recordedCloudBytes(m.k);
                c.width = uint32_t(c.data.size() / 20);
                c.point_step = 20;
                c.row_step = c.width * 20;
                c.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"intensity", 12, 7, 1},
                            {"t", 16, 6, 1}};
                out.push_back({m.topic, "sensor_msgs/msg/PointCloud2", m.record_ns, cdr(c)});
                break;
            }
            case Recorded::Kind::Imu: {
                Imu i;
                i.stamp = stamp;
                i.frame = m.frame;
                i.acc = {0, 0, 9.81};
                i.gyro = {0, 0, 0.1};
                out.push_back({m.topic, "sensor_msgs/msg/Imu", m.record_ns, cdr(i)});
                break;
            }
            case Recorded::Kind::Gt: {
                Odometry o;
                o.stamp = stamp;
                o.frame = m.frame;
                o.child = "base_link";
                o.pose = poseOf(recordedGt(m.k));
                out.push_back({m.topic, "nav_msgs/msg/Odometry", m.record_ns, cdr(o)});
                break;
            }
        }
    }
    return out;
}

#ifdef SUPERLOC_HAVE_ROS1
/// The recording as a ROS 1 bag, written by rosbag_storage.
inline void writeRos1Recording(const std::string& path, const Recording& r) {
    const auto rosTime = [](int64_t ns) { return ros::Time(uint32_t(ns / 1000000000), uint32_t(ns % 1000000000)); };
    const auto header = [&](std_msgs::Header& h, const Recorded& m) {
        h.stamp = rosTime(m.stamp_ns);
        h.frame_id = m.frame;
    };
    const auto setPose = [](geometry_msgs::Pose& p, const Pose& x) {
        p.position.x = x.x, p.position.y = x.y, p.position.z = x.z;
        p.orientation.x = x.qx, p.orientation.y = x.qy, p.orientation.z = x.qz;
        p.orientation.w = x.qw;
    };
    rosbag::Bag b(path, rosbag::bagmode::Write);
    for (const auto& m : recording(r)) {
        const ros::Time rec = rosTime(m.record_ns);
        switch (m.kind) {
            case Recorded::Kind::Tf: {
                tf2_msgs::TFMessage tf;
                for (const auto& [child, T] :
                     {std::pair{"lidar", kT_base_lidar}, std::pair{"imu_link", kT_base_imu}}) {
                    geometry_msgs::TransformStamped x;
                    x.header.stamp = rosTime(m.stamp_ns);
                    x.header.frame_id = "base_link";
                    x.child_frame_id = child;
                    const Pose p = poseOf(T);
                    x.transform.translation.x = p.x, x.transform.translation.y = p.y;
                    x.transform.translation.z = p.z;
                    x.transform.rotation.x = p.qx, x.transform.rotation.y = p.qy;
                    x.transform.rotation.z = p.qz, x.transform.rotation.w = p.qw;
                    tf.transforms.push_back(x);
                }
                b.write(m.topic, rec, tf);
                break;
            }
            case Recorded::Kind::Cloud: {
                sensor_msgs::PointCloud2 pc;
                header(pc.header, m);
                pc.data = recordedCloudBytes(m.k);
                pc.height = 1;
                pc.width = uint32_t(pc.data.size() / 20);
                pc.point_step = 20;
                pc.row_step = pc.width * 20;
                for (const auto& [name, offset, type] :
                     {std::tuple{"x", 0u, 7}, std::tuple{"y", 4u, 7}, std::tuple{"z", 8u, 7},
                      std::tuple{"intensity", 12u, 7}, std::tuple{"t", 16u, 6}}) {
                    sensor_msgs::PointField f;
                    f.name = name;
                    f.offset = offset;
                    f.datatype = uint8_t(type);
                    f.count = 1;
                    pc.fields.push_back(f);
                }
                b.write(m.topic, rec, pc);
                break;
            }
            case Recorded::Kind::Imu: {
                sensor_msgs::Imu i;
                header(i.header, m);
                i.linear_acceleration.z = 9.81;
                i.angular_velocity.z = 0.1;
                b.write(m.topic, rec, i);
                break;
            }
            case Recorded::Kind::Gt: {
                nav_msgs::Odometry o;
                header(o.header, m);
                o.child_frame_id = "base_link";
                setPose(o.pose.pose, poseOf(recordedGt(m.k)));
                b.write(m.topic, rec, o);
                break;
            }
        }
    }
    b.close();
}
#endif

}  // namespace superloc::testing::bag
