// Prior map from a rawlog's scans and their poses (app superloc-map): streaming, memory bounded
// by the map (one running centroid per occupied voxel), not by the rawlog.
#pragma once

#include <mrpt/system/COutputLogger.h>
#include <superloc/core/types.h>
#include <superloc/io/importers.h>
#include <superloc/io/rawlog.h>

#include <string>

namespace superloc::map {

struct MapBuildOptions {
    std::string rawlog;     ///< input rawlog (this or `simplemap`)
    /// input MRPT .simplemap instead of a rawlog: each keyframe's point-cloud observations at
    /// the keyframe pose (the mean of its PDF) times their sensorPose; `poses_tum` unused
    std::string simplemap;
    std::string poses_tum;  ///< TUM poses of the scans; empty = the rawlog's `gt` poses
    double voxel = 0.1;     ///< [m] output voxel size; each voxel keeps its points' centroid (0 = all)
    double min_range = 0.5; ///< [m] scan points closer to the sensor are dropped (e.g. the carrier)
    double max_range = 0;   ///< [m] farther points are dropped (0 = no limit)
    /// The poses are T_map_imu (body) instead of T_map_lidar: points also go through each scan's
    /// sensorPose (T_imu_lidar).
    bool body_poses = false;
    /// [s] a scan whose time is not within the poses' span (or lies in a gap longer than this)
    /// gets no pose and is skipped (counted)
    double max_pose_gap = 5.0;
    /// Also compute each map point's normal (PCA of its 10 nearest map points within
    /// max(0.5 m, 5 voxels)), flipped toward the side its scans saw it from, and store it in the
    /// output (PriorMap::load then orients its normals the same way).
    bool normals = true;
    io::RawlogParams rawlog_params;  ///< labels ([rawlog] section)
};

struct MapBuildResult {
    size_t scans_used = 0;          ///< scans placed in the map
    size_t scans_without_pose = 0;  ///< scans outside the poses' time span (skipped)
    size_t points_in = 0;           ///< scan points accumulated (after the range filter)
    size_t map_points = 0;          ///< points of the output map
    size_t poses = 0;               ///< poses available (TUM lines or rawlog `gt`)
    double normals_seconds = 0;     ///< time spent on the normals
};

class MapBuilder : public mrpt::system::COutputLogger {
   public:
    explicit MapBuilder(const MapBuildOptions& options);

    /// Reads the rawlog (twice when the poses come from its `gt` observations), places every
    /// scan at its pose and returns the voxelized map (with mean intensity when scans have it).
    /// Throws std::runtime_error with a one-line message on bad input.
    PointCloud build(const io::ProgressFn& progress = {});

    const MapBuildResult& result() const { return result_; }

   private:
    MapBuildOptions opts_;
    MapBuildResult result_;
};

}  // namespace superloc::map
