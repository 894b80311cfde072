// RawlogWriter: observations-only rawlog, gz-compressed (readable by rawlog-edit).
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/serialization/CArchive.h>
#include <superloc/core/mrpt_conversions.h>
#include <superloc/io/rawlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace superloc::io {

struct RawlogWriter::Impl {
    std::string path;
    mrpt::io::CFileGZOutputStream file;
    bool open = false;
};

RawlogWriter::RawlogWriter(const std::string& path) : impl_(std::make_unique<Impl>()) {
    impl_->path = path;
    if (!impl_->file.open(path))
        throw std::runtime_error(path + ": cannot open rawlog for writing");
    impl_->open = true;
}

RawlogWriter::~RawlogWriter() {
    try {
        close();
    } catch (...) {
    }
}

void RawlogWriter::write(const mrpt::obs::CObservation& obs) {
    if (!impl_->open) throw std::runtime_error(impl_->path + ": rawlog writer already closed");
    try {
        auto arch = mrpt::serialization::archiveFrom(impl_->file);
        arch << obs;
    } catch (const std::exception& e) {
        throw std::runtime_error(impl_->path +
                                 ": write error: " + std::string(e.what()).substr(0, 200));
    }
}

void RawlogWriter::writeScan(const Scan& scan, const std::string& label) {
    auto obs = mrpt::obs::CObservationPointCloud::Create();
    obs->timestamp = mrpt::Clock::fromDouble(scan.t);
    obs->sensorLabel = label;
    obs->sensorPose = toMrpt(scan.T_imu_lidar);
    auto pts = mrpt::maps::CPointsMapXYZI::Create();
    pts->reserve(scan.points.size());
    const bool has_i = scan.intensity.size() == scan.points.size();
    for (size_t i = 0; i < scan.points.size(); ++i) {
        const auto& p = scan.points[i];
        pts->insertPointFast(p.x(), p.y(), p.z());
        pts->setPointIntensity(i, has_i ? scan.intensity[i] : 0.0f);
    }
    pts->mark_as_modified();
    obs->pointcloud = pts;
    write(*obs);
}

void RawlogWriter::writeTimedScan(const Scan& scan, const std::string& label,
                                  float intensity_max) {
    if (scan.rel_time.size() != scan.points.size())
        throw std::runtime_error(impl_->path + ": writeTimedScan: " +
                                 std::to_string(scan.rel_time.size()) + " point times for " +
                                 std::to_string(scan.points.size()) + " points");
    mrpt::obs::CObservationVelodyneScan obs;
    obs.timestamp = mrpt::Clock::fromDouble(scan.t);
    obs.originalReceivedTimestamp = obs.timestamp;
    obs.sensorLabel = label;
    obs.sensorPose = toMrpt(scan.T_imu_lidar);
    auto& pc = obs.point_cloud;
    const size_t n = scan.points.size();
    const bool has_i = scan.intensity.size() == n;
    pc.x.resize(n);
    pc.y.resize(n);
    pc.z.resize(n);
    pc.intensity.resize(n);
    pc.timestamp.resize(n);
    for (size_t i = 0; i < n; ++i) {
        pc.x[i] = scan.points[i].x();
        pc.y[i] = scan.points[i].y();
        pc.z[i] = scan.points[i].z();
        const float v = has_i && intensity_max > 0 ? scan.intensity[i] / intensity_max : 0.0f;
        pc.intensity[i] = static_cast<uint8_t>(std::lround(255.0f * std::clamp(v, 0.0f, 1.0f)));
        pc.timestamp[i] =
            obs.timestamp + std::chrono::round<mrpt::Clock::duration>(
                                std::chrono::duration<double>(double(scan.rel_time[i])));
    }
    write(obs);
}

void RawlogWriter::writeImu(const ImuSample& imu, const std::string& label) {
    using namespace mrpt::obs;
    CObservationIMU obs;
    obs.timestamp = mrpt::Clock::fromDouble(imu.t);
    obs.sensorLabel = label;
    obs.set(IMU_X_ACC, imu.acc.x());
    obs.set(IMU_Y_ACC, imu.acc.y());
    obs.set(IMU_Z_ACC, imu.acc.z());
    obs.set(IMU_WX, imu.gyro.x());
    obs.set(IMU_WY, imu.gyro.y());
    obs.set(IMU_WZ, imu.gyro.z());
    write(obs);
}

void RawlogWriter::writePose(const PoseStamped& pose, const std::string& label) {
    mrpt::obs::CObservationRobotPose obs;
    obs.timestamp = mrpt::Clock::fromDouble(pose.t);
    obs.sensorLabel = label;
    obs.pose.mean = toMrpt(pose.pose);
    obs.pose.cov = covToMrpt(pose.cov ? *pose.cov : Mat6d(Mat6d::Identity() * 1e-6));
    write(obs);
}

void RawlogWriter::close() {
    if (!impl_->open) return;
    impl_->open = false;
    impl_->file.close();
}

}  // namespace superloc::io
