// MRPT map files as prior maps: `.simplemap` (mrpt::maps::CSimpleMap: keyframes = a pose PDF +
// a sensory frame of observations) and `.pointsmap` (one serialized mrpt::maps::CPointsMap
// subclass — CSimplePointsMap, CPointsMapXYZI, CColouredPointsMap, ... — gz-compressed or not,
// as `archiveFrom(CFileGZOutputStream) << map` writes it). io::loadPointCloud reads both by
// extension, so `superloc-localize --map` takes them; `superloc-map --simplemap` builds a voxel
// map from a simplemap's scans.
#pragma once

#include <superloc/core/types.h>
#include <superloc/io/rawlog.h>

#include <functional>
#include <string>

namespace superloc::io {

/// What a simplemap held.
struct SimpleMapStats {
    size_t keyframes = 0;
    size_t scans = 0;               ///< observations turned into points
    size_t other_observations = 0;  ///< observations without points (IMU, images, ...): skipped
    size_t invalid_points = 0;      ///< NaN/inf points dropped
};

/// Visits the point-cloud-like observations of a simplemap, keyframe by keyframe:
/// CObservationPointCloud, CObservationVelodyneScan and CObservationRotatingScan as the rawlog
/// reader converts them (points in the sensor frame, scan.T_imu_lidar = the observation's
/// sensorPose), CObservation2DRangeScan and CObservation3DRangeScan through MRPT's own point
/// insertion (points in the keyframe's body frame, T_imu_lidar = identity). `T_map_body` is the
/// mean of the keyframe's pose PDF; a point p of `scan` is at T_map_body * scan.T_imu_lidar * p.
/// Throws std::runtime_error naming the file when it is missing or not a simplemap.
SimpleMapStats forEachSimpleMapScan(
    const std::string& path, const std::function<void(const Scan&, const SE3d& T_map_body)>& fn,
    const RawlogParams& params = {});

/// Every point of a simplemap in the map frame (with intensity when every scan has it).
PointCloud loadSimpleMap(const std::string& path, SimpleMapStats* stats = nullptr);

/// A serialized MRPT point map (.pointsmap): points (+ intensity of a CPointsMapXYZI).
PointCloud loadMrptPointsMap(const std::string& path);
/// Writes a CPointsMapXYZI (with intensity) or a CSimplePointsMap, gz-compressed.
void saveMrptPointsMap(const std::string& path, const PointCloud& cloud);

}  // namespace superloc::io
