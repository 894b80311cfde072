// MRPT .simplemap and serialized point maps (.pointsmap) as prior maps. See mrpt_maps.h.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <superloc/core/mrpt_conversions.h>
#include <superloc/io/mrpt_maps.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "obs_to_scan.h"

namespace superloc::io {

namespace {

/// Points of a CPointsMap (with intensity when it is a CPointsMapXYZI).
void appendPoints(const mrpt::maps::CPointsMap& m, std::vector<Vec3f>& pts,
                  std::vector<float>* intensity) {
    const auto& xs = m.getPointsBufferRef_x();
    const auto& ys = m.getPointsBufferRef_y();
    const auto& zs = m.getPointsBufferRef_z();
    const auto* xyzi = dynamic_cast<const mrpt::maps::CPointsMapXYZI*>(&m);
    for (size_t i = 0; i < xs.size(); ++i) {
        pts.emplace_back(xs[i], ys[i], zs[i]);
        if (intensity) intensity->push_back(xyzi ? xyzi->getPointIntensity(i) : 0.f);
    }
}

}  // namespace

SimpleMapStats forEachSimpleMapScan(const std::string& path,
                                    const std::function<void(const Scan&, const SE3d&)>& fn,
                                    const RawlogParams& params_in) {
    if (!std::filesystem::exists(path)) throw std::runtime_error(path + ": file not found");
    mrpt::maps::CSimpleMap sm;
    if (!sm.loadFromFile(path))
        throw std::runtime_error(path + ": not a readable MRPT simplemap (CSimpleMap)");
    RawlogParams params = params_in;
    params.scan_period = 0;  // no azimuth-derived time: maps do not deskew
    SimpleMapStats st;
    st.keyframes = sm.size();
    for (size_t k = 0; k < sm.size(); ++k) {
        const auto& [pose_pdf, sf] = sm.getAsPair(k);
        if (!pose_pdf || !sf) continue;
        mrpt::poses::CPose3D mean;
        pose_pdf->getMean(mean);
        const SE3d T_map_body = toEigen(mean);
        for (const auto& obs : *sf) {
            if (!obs) continue;
            Scan scan;
            const auto kind = detail::lidarFromObservation(*obs, params, scan, st.invalid_points);
            if (kind == detail::LidarConversion::NotLidar &&
                (IS_CLASS(*obs, mrpt::obs::CObservation2DRangeScan) ||
                 IS_CLASS(*obs, mrpt::obs::CObservation3DRangeScan))) {
                // MRPT's own insertion: points in the body frame (sensorPose applied).
                mrpt::maps::CSimplePointsMap m;
                m.insertionOptions.minDistBetweenLaserPoints = 0;
                m.insertionOptions.also_interpolate = false;
                m.insertObservation(*obs);
                scan = Scan();
                scan.t = mrpt::Clock::toDouble(obs->timestamp);
                appendPoints(m, scan.points, nullptr);
                if (!scan.empty()) {
                    fn(scan, T_map_body);
                    ++st.scans;
                    continue;
                }
            }
            if (kind != detail::LidarConversion::Ok || scan.empty()) {
                ++st.other_observations;
                continue;
            }
            fn(scan, T_map_body);
            ++st.scans;
        }
    }
    return st;
}

PointCloud loadSimpleMap(const std::string& path, SimpleMapStats* stats) {
    PointCloud c;
    bool all_intensity = true;
    const auto st = forEachSimpleMapScan(path, [&](const Scan& s, const SE3d& T_map_body) {
        const SE3d T = T_map_body * s.T_imu_lidar;
        const Eigen::Matrix3f R = T.linear().cast<float>();
        const Vec3d t = T.translation();
        for (const auto& p : s.points)
            c.points.push_back(((R * p).cast<double>() + t).cast<float>());
        if (s.intensity.size() == s.size())
            c.intensity.insert(c.intensity.end(), s.intensity.begin(), s.intensity.end());
        else
            all_intensity = false;
    });
    if (!all_intensity) c.intensity.clear();
    if (c.empty())
        throw std::runtime_error(path + ": the simplemap has no point-cloud observations (" +
                                 std::to_string(st.keyframes) + " keyframes, " +
                                 std::to_string(st.other_observations) + " other observations)");
    if (stats) *stats = st;
    return c;
}

PointCloud loadMrptPointsMap(const std::string& path) {
    mrpt::serialization::CSerializable::Ptr obj;
    try {
        mrpt::io::CFileGZInputStream f(path);
        obj = mrpt::serialization::archiveFrom(f).ReadObject();
    } catch (const std::exception& e) {
        throw std::runtime_error(path +
                                 ": not a readable MRPT point map: " + detail::firstLine(e.what()));
    }
    const auto m = std::dynamic_pointer_cast<mrpt::maps::CPointsMap>(obj);
    if (!m)
        throw std::runtime_error(path + ": holds an MRPT " +
                                 std::string(obj ? obj->GetRuntimeClass()->className : "null") +
                                 ", not a point map (CPointsMap)");
    PointCloud c;
    const bool xyzi = dynamic_cast<const mrpt::maps::CPointsMapXYZI*>(m.get()) != nullptr;
    appendPoints(*m, c.points, xyzi ? &c.intensity : nullptr);
    return c;
}

void saveMrptPointsMap(const std::string& path, const PointCloud& c) {
    mrpt::io::CFileGZOutputStream f;
    if (!f.open(path)) throw std::runtime_error(path + ": cannot open for writing");
    auto a = mrpt::serialization::archiveFrom(f);
    if (c.intensity.size() == c.size()) {
        mrpt::maps::CPointsMapXYZI m;
        m.reserve(c.size());
        for (size_t i = 0; i < c.size(); ++i)
            m.insertPointFast(c.points[i].x(), c.points[i].y(), c.points[i].z()),
                m.setPointIntensity(i, c.intensity[i]);
        a << m;
    } else {
        mrpt::maps::CSimplePointsMap m;
        m.reserve(c.size());
        for (const auto& p : c.points) m.insertPointFast(p.x(), p.y(), p.z());
        a << m;
    }
}

}  // namespace superloc::io
