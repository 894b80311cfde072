// MRPT LiDAR observations -> superloc::Scan (doc/design.md#3-data-conventions: per-point time).
#include "obs_to_scan.h"

#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/poses/CPose3D.h>
#include <superloc/core/mrpt_conversions.h>

#include <chrono>
#include <cmath>
#include <sstream>

namespace superloc::io::detail {

namespace {

bool finite3(float x, float y, float z) {
    return std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
}

/// Copies an MRPT point map (with intensity when it is a CPointsMapXYZI).
void copyPointsMap(const mrpt::maps::CPointsMap& m, Scan& scan, size_t& invalid) {
    const auto& xs = m.getPointsBufferRef_x();
    const auto& ys = m.getPointsBufferRef_y();
    const auto& zs = m.getPointsBufferRef_z();
    const auto* xyzi = dynamic_cast<const mrpt::maps::CPointsMapXYZI*>(&m);
    const size_t n = m.size();
    scan.points.reserve(n);
    if (xyzi) scan.intensity.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        if (!finite3(xs[i], ys[i], zs[i])) {
            ++invalid;
            continue;
        }
        scan.points.emplace_back(xs[i], ys[i], zs[i]);
        if (xyzi) scan.intensity.push_back(xyzi->getPointIntensity_fast(i));
    }
}

/// The valid points of a Velodyne point cloud, with their intensity (0..1) and, when the cloud
/// has per-point timestamps, their time relative to t0 (the observation's time).
void copyVelodyneCloud(const mrpt::obs::CObservationVelodyneScan::TPointCloud& pc, mrpt::Clock::time_point t0,
                       Scan& scan, size_t& invalid) {
    const bool has_t = pc.timestamp.size() == pc.size();
    const bool has_i = pc.intensity.size() == pc.size();
    scan.points.reserve(pc.size());
    scan.intensity.reserve(pc.size());
    if (has_t) scan.rel_time.reserve(pc.size());
    for (size_t i = 0; i < pc.size(); ++i) {
        if (!finite3(pc.x[i], pc.y[i], pc.z[i])) {
            ++invalid;
            continue;
        }
        scan.points.emplace_back(pc.x[i], pc.y[i], pc.z[i]);
        scan.intensity.push_back(has_i ? pc.intensity[i] / 255.0f : 0.0f);
        if (has_t)
            scan.rel_time.push_back(static_cast<float>(std::chrono::duration<double>(pc.timestamp[i] - t0).count()));
    }
}

/// A Velodyne observation: its packets decoded to a cloud with per-point times, or (without
/// packets) the point_cloud stored with per-point timestamps (RawlogWriter::writeTimedScan)
/// taken as it is.
void fromVelodyne(const mrpt::obs::CObservationVelodyneScan& in, Scan& scan, size_t& invalid) {
    if (in.scan_packets.empty() && in.point_cloud.size() > 0) {
        copyVelodyneCloud(in.point_cloud, in.timestamp, scan, invalid);
        return;
    }
    mrpt::obs::CObservationVelodyneScan obs(in);  // generatePointCloud() fills a member
    mrpt::obs::CObservationVelodyneScan::TGeneratePointCloudParameters gp;
    gp.generatePerPointTimestamp = true;
    obs.generatePointCloud(gp);
    copyVelodyneCloud(obs.point_cloud, in.timestamp, scan, invalid);
}

/// Vertical angle [rad] of row `row` for the models MRPT 2.5.8's fromVelodyne() writes (it
/// keeps no calibration in the observation: its header says "TODO: Calibration"). Rows are
/// Velodyne laser ids. Empty when the model is unknown.
std::vector<double> rowElevations(const mrpt::obs::CObservationRotatingScan& o) {
    std::vector<double> el;
    const double deg = M_PI / 180.0;
    if (o.lidarModel == "VLP-16" && o.rowCount == 16) {
        for (int i = 0; i < 16; ++i) el.push_back((i % 2 == 0 ? -15 + i : i) * deg);
    } else if (o.lidarModel == "HDL-32E" && o.rowCount == 32) {
        for (int i = 0; i < 32; ++i)
            el.push_back(((i % 2 == 0) ? -30.67 + (i / 2) * 1.333 : -9.33 + (i / 2) * 1.333) * deg);
    } else if (o.rowCount == 1) {
        el.push_back(0.0);  // from a 2D scan
    }
    return el;
}

bool fromRotating(const mrpt::obs::CObservationRotatingScan& o, Scan& scan, size_t& invalid) {
    const auto el = rowElevations(o);
    if (el.empty() || o.columnCount == 0) return false;
    // fromVelodyne() puts firing k of laser L at column k / rowCount of a 16x oversized image
    // and measures azimuth clockwise; fromScan2D() uses every column, counter-clockwise.
    const bool velodyne = o.rowCount > 1;
    const double cols = velodyne ? double(o.columnCount) / o.rowCount : double(o.columnCount);
    const double sense = velodyne ? -1.0 : 1.0;
    const bool has_i =
        o.intensityImage.rows() == o.rowCount && o.intensityImage.cols() == o.columnCount;
    for (int c = 0; c < o.columnCount; ++c) {
        const double frac = c / cols;
        const double az = sense * (o.startAzimuth + o.azimuthSpan * frac);
        for (int r = 0; r < o.rowCount; ++r) {
            const uint16_t raw = o.rangeImage(r, c);
            if (raw == 0) continue;
            const double range = raw * o.rangeResolution;
            const Vec3f p(float(range * std::cos(el[r]) * std::cos(az)),
                          float(range * std::cos(el[r]) * std::sin(az)),
                          float(range * std::sin(el[r])));
            if (!p.allFinite()) {
                ++invalid;
                continue;
            }
            scan.points.push_back(p);
            scan.intensity.push_back(has_i ? o.intensityImage(r, c) / 255.0f : 0.0f);
            scan.rel_time.push_back(float(frac * o.sweepDuration));
        }
    }
    return true;
}

}  // namespace

std::string firstLine(const std::string& what) {
    // MRPT: "==== MRPT exception ====\nMessage: outer\n...Original exception:\n...Message: inner".
    // Keep the outermost and innermost messages; plain exceptions: their first line.
    std::istringstream ss(what);
    std::string line, first, last;
    while (std::getline(ss, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.rfind("Message:", 0) == 0) {
            line = line.substr(line.find_first_not_of(' ', 8) == std::string::npos
                                   ? 8
                                   : line.find_first_not_of(' ', 8));
            if (first.empty()) first = line;
            last = line;
        } else if (first.empty() && !line.empty() && line.rfind("====", 0) != 0 &&
                   what.find("Message:") == std::string::npos) {
            first = last = line;
            break;
        }
    }
    std::string s = first == last ? first : first + ": " + last;
    if (s.empty()) s = "unknown error";
    if (s.size() > 300) s = s.substr(0, 300) + "...";
    return s;
}

void timeFromAzimuth(Scan& scan, const RawlogParams& params) {
    if (params.scan_period <= 0) return;
    constexpr double kTwoPi = 2.0 * M_PI;
    const double start = params.start_azimuth_deg * M_PI / 180.0;
    scan.rel_time.resize(scan.points.size());
    for (size_t i = 0; i < scan.points.size(); ++i) {
        const auto& p = scan.points[i];
        double d = params.rotation_sense * (std::atan2(p.y(), p.x()) - start);
        d = std::fmod(d, kTwoPi);
        if (d < 0) d += kTwoPi;
        scan.rel_time[i] = static_cast<float>((d / kTwoPi - 1.0) * params.scan_period);
    }
}

LidarConversion lidarFromObservation(const mrpt::obs::CObservation& obs, const RawlogParams& params,
                                     Scan& scan, size_t& invalid_points) {
    using namespace mrpt::obs;
    const bool is_pc = dynamic_cast<const CObservationPointCloud*>(&obs) != nullptr;
    const auto* velo = dynamic_cast<const CObservationVelodyneScan*>(&obs);
    const auto* rot = dynamic_cast<const CObservationRotatingScan*>(&obs);
    if (!is_pc && !velo && !rot) return LidarConversion::NotLidar;

    scan = Scan();
    scan.t = mrpt::Clock::toDouble(obs.timestamp);
    scan.label = obs.sensorLabel;
    mrpt::poses::CPose3D sensor_pose;
    obs.getSensorPose(sensor_pose);
    scan.T_imu_lidar = toEigen(sensor_pose);

    if (is_pc) {
        const auto& pc = static_cast<const CObservationPointCloud&>(obs);
        if (pc.isExternallyStored()) pc.load();
        if (pc.pointcloud) copyPointsMap(*pc.pointcloud, scan, invalid_points);
        timeFromAzimuth(scan, params);
    } else if (velo) {
        fromVelodyne(*velo, scan, invalid_points);
    } else if (!fromRotating(*rot, scan, invalid_points)) {
        return LidarConversion::Unsupported;
    }
    return LidarConversion::Ok;
}

}  // namespace superloc::io::detail
