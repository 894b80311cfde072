#include <superloc/fusion/state.h>

namespace superloc::fusion {

SE3d FrameState::T_map_imu() const {
    SE3d T = SE3d::Identity();
    T.linear() = Eigen::Quaterniond(pose[6], pose[3], pose[4], pose[5]).normalized().toRotationMatrix();
    T.translation() = Vec3d(pose[0], pose[1], pose[2]);
    return T;
}

void FrameState::setPose(const SE3d& T) {
    const Eigen::Quaterniond q(T.linear());
    pose[0] = T.translation().x();
    pose[1] = T.translation().y();
    pose[2] = T.translation().z();
    pose[3] = q.x();
    pose[4] = q.y();
    pose[5] = q.z();
    pose[6] = q.w();
}

void FrameState::setVelocity(const Vec3d& v) {
    for (int k = 0; k < 3; ++k) speed_bias[k] = v[k];
}

imu::ImuBias FrameState::bias() const {
    imu::ImuBias b;
    b.acc = Vec3d(speed_bias[3], speed_bias[4], speed_bias[5]);
    b.gyro = Vec3d(speed_bias[6], speed_bias[7], speed_bias[8]);
    return b;
}

void FrameState::setBias(const imu::ImuBias& b) {
    for (int k = 0; k < 3; ++k) {
        speed_bias[3 + k] = b.acc[k];
        speed_bias[6 + k] = b.gyro[k];
    }
}

}  // namespace superloc::fusion
