// Importers of scan folders into rawlogs (app superloc-import).
#pragma once

#include <superloc/core/types.h>

#include <functional>
#include <string>
#include <vector>

namespace superloc::io {

struct ImportResult {
    size_t scans = 0;           ///< LiDAR observations written
    size_t points = 0;          ///< total points written
    size_t gt_poses = 0;        ///< `gt` CObservationRobotPose written
    size_t dropped_points = 0;  ///< NaN/inf points dropped
    size_t imu = 0;             ///< CObservationIMU written (bag topic or --imu-csv)
    size_t odom_alt = 0;        ///< `odom_alt` CObservationRobotPose written (topic or --odom-csv)
    size_t empty_scans = 0;     ///< scans with no valid point, not written (the reader would skip them)
    std::string first_empty;    ///< the first of them: its file, or "topic at t"
};

/// Samples from other files (--imu-csv, --odom-csv) written into an import, interleaved with
/// the scans by time.
struct ImportExtras {
    std::vector<ImuSample> imu;
    Trajectory odom_alt;
    std::string imu_label = "imu";
    std::string odom_alt_label = "odom_alt";
};

/// IMU CSV: one sample per line, `t, ax, ay, az, wx, wy, wz` ([s], [m/s^2], [rad/s], body
/// frame), separated by commas and/or blanks; an optional header line (first line, not
/// numeric), '#' comments and blank lines are skipped. Times must increase. Throws
/// std::runtime_error "FILE:LINE: reason".
std::vector<ImuSample> loadImuCsv(const std::string& path);

/// Odometry CSV: `t x y z qx qy qz qw` (T_odom_body) and optionally 21 more values, the upper
/// triangle (row by row) of the 6x6 pose covariance in x y z roll pitch yaw order. Same syntax
/// and errors as loadImuCsv; quaternions are normalized (error when far from unit length).
Trajectory loadOdomCsv(const std::string& path);

/// Progress callback: (done, total).
using ProgressFn = std::function<void(size_t, size_t)>;

/// KITTI odometry folder: DIR/velodyne/NNNNNN.bin, DIR/times.txt (seconds, one per scan);
/// optional TUM poses (one per scan in order, matched by index, or by timestamp when the TUM
/// timestamps equal times.txt). `times_file` overrides DIR/times.txt when not empty.
ImportResult importKitti(const std::string& dir, const std::string& poses_tum,
                         const std::string& times_file, const std::string& out_rawlog,
                         const ProgressFn& progress = {}, const ImportExtras& extras = {});

/// Folder of PCD scans (sorted by file name) with optional TUM poses (one per scan, in order;
/// the scan times are the TUM timestamps) or a times file (one time per line).
ImportResult importPcdFolder(const std::string& dir, const std::string& poses_tum,
                             const std::string& times_file, const std::string& out_rawlog,
                             const ProgressFn& progress = {}, const ImportExtras& extras = {});

}  // namespace superloc::io
