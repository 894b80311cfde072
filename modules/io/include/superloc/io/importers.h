// Importers of scan folders into rawlogs (app superloc-import).
#pragma once

#include <functional>
#include <string>

namespace superloc::io {

struct ImportResult {
    size_t scans = 0;           ///< LiDAR observations written
    size_t points = 0;          ///< total points written
    size_t gt_poses = 0;        ///< `gt` CObservationRobotPose written
    size_t dropped_points = 0;  ///< NaN/inf points dropped
};

/// Progress callback: (done, total).
using ProgressFn = std::function<void(size_t, size_t)>;

/// KITTI odometry folder: DIR/velodyne/NNNNNN.bin, DIR/times.txt (seconds, one per scan);
/// optional TUM poses (one per scan in order, matched by index, or by timestamp when the TUM
/// timestamps equal times.txt). `times_file` overrides DIR/times.txt when not empty.
ImportResult importKitti(const std::string& dir, const std::string& poses_tum,
                         const std::string& times_file, const std::string& out_rawlog,
                         const ProgressFn& progress = {});

/// Folder of PCD scans (sorted by file name) with optional TUM poses (one per scan, in order;
/// the scan times are the TUM timestamps) or a times file (one time per line).
ImportResult importPcdFolder(const std::string& dir, const std::string& poses_tum,
                             const std::string& times_file, const std::string& out_rawlog,
                             const ProgressFn& progress = {});

}  // namespace superloc::io
