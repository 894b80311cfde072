// Private to io: conversion of MRPT LiDAR observations into superloc::Scan.
#pragma once

#include <superloc/io/rawlog.h>

namespace mrpt::obs {
class CObservation;
}

namespace superloc::io::detail {

/// Unsupported: a CObservationRotatingScan of a model whose beam angles are unknown.
enum class LidarConversion { NotLidar, Ok, Unsupported };

/// If `obs` is a CObservationPointCloud, CObservationVelodyneScan or CObservationRotatingScan,
/// fills `scan` (sensor frame, NaN/inf points dropped and added to `invalid_points`) and
/// returns Ok; otherwise NotLidar. Velodyne scans get their per-point times from MRPT (relative
/// to the observation timestamp, so >= 0), as do rotating scans (from their column);
/// point clouds get them from the azimuth (<= 0).
LidarConversion lidarFromObservation(const mrpt::obs::CObservation& obs, const RawlogParams& params,
                                     Scan& scan, size_t& invalid_points);

/// Per-point time from the azimuth for a sweep that ends at scan.t (rel_time in
/// [-scan_period, 0)); does nothing when params.scan_period is 0.
void timeFromAzimuth(Scan& scan, const RawlogParams& params);

/// First line of an exception message (MRPT messages carry a multi-line trace), trimmed.
std::string firstLine(const std::string& what);

}  // namespace superloc::io::detail
