// The synthetic content shared by the ROS 1 (tests/io/test_rosbag.cpp) and ROS 2
// (tests/io/test_ros2bag.cpp) round-trip bags, and the checks of what the import makes of it:
// the k-th IMU sample, odometry message (odom_alt, with a covariance) and ground-truth pose.
#pragma once

#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/core/types.h>

#include <algorithm>
#include <cstddef>

namespace superloc::testing::bag {

/// Extrinsics on /tf_static: base_link -> lidar and base_link -> imu_link.
inline const SE3d kT_base_lidar = makePoseRPY(0.3, 0.1, 1.2, 0.0, 0.02, 0.5);
inline const SE3d kT_base_imu = makePoseRPY(-0.1, 0.0, 0.4, 0.0, 0.0, -0.3);

/// Entry i (row-major) of the k-th message's symmetric 6x6 covariance, distinct values (MRPT
/// stores the upper triangle of a CPose3DPDFGaussian).
inline double symCov(size_t i, int k) {
    const size_t r = std::min(i / 6, i % 6), c = std::max(i / 6, i % 6);
    return (r == c ? 0.1 : 0.001) * double(r * 6 + c + 1) + k;
}

/// Sample k: t = t0 + 0.01 k, acc (0.1 k, -0.2, 9.81), gyro (0.01, -0.02 k, 0.5).
inline void expectImu(const superloc::ImuSample& m, int k, double t0) {
    EXPECT_NEAR(m.t, t0 + 0.01 * k, 1e-6);
    EXPECT_EQ(m.acc, Vec3d(0.1 * k, -0.2, 9.81));
    EXPECT_EQ(m.gyro, Vec3d(0.01, -0.02 * k, 0.5));
}

/// Odometry k: base_link at (0.5 k, 0.1 k, 0), yaw 0.1 k, read as T_odom_body with body =
/// imu_link; its covariance symCov(., k).
inline void expectOdomAlt(const superloc::PoseStamped& o, int k) {
    const SE3d want = makePoseRPY(k * 0.5, 0.1 * k, 0, 0, 0, 0.1 * k) * kT_base_imu;
    EXPECT_TRUE(o.pose.isApprox(want, 1e-9)) << "odometry " << k;
    ASSERT_TRUE(o.cov.has_value());
    for (int i = 0; i < 36; ++i) EXPECT_DOUBLE_EQ((*o.cov)(i / 6, i % 6), symCov(size_t(i), k)) << i;
}

/// Ground truth k: base_link at (10 + 0.5 k, 5, 1), roll 0.01, yaw 0.2 + 0.1 k, written as
/// T_map_lidar.
inline void expectGroundTruth(const superloc::PoseStamped& p, int k) {
    const SE3d want = makePoseRPY(10 + k * 0.5, 5, 1, 0.01, 0, 0.2 + 0.1 * k) * kT_base_lidar;
    EXPECT_TRUE(p.pose.isApprox(want, 1e-9)) << "gt " << k;
}

}  // namespace superloc::testing::bag
