// Outputs of a localization run (doc/localizer.md), written progressively: the app layer's writers.
//   trajectory.tum  one pose per frame (flushed per line)
//   frames.csv      one localization::FrameReport per line (flushed per line), header below
//   trajectory_cov.txt  each pose's 6 x 6 covariance, ROS's convention (flushed per line)
//   summary.json    counts and timing statistics (at the end)
//   localized_map.pcd  every scan's points at its estimate, voxelized (at the end)
//   report.html     the run at a glance (run_report.h; at the end, unless switched off)
#pragma once

#include <superloc/core/types.h>
#include <superloc/core/voxel.h>
#include <superloc/io/json_file.h>
#include <superloc/io/rawlog.h>
#include <superloc/localization/frame_report.h>
#include <superloc/app/run_report.h>

#include <fstream>
#include <memory>
#include <optional>
#include <array>
#include <string>
#include <vector>

namespace superloc::io {
class TumWriter;
}

namespace superloc::app {

/// The frames.csv header (doc/design.md#9-command-line columns first, then the localizer's own).
std::string framesCsvHeader();
/// One frames.csv line for a report; `T` is the pose written (lidar or body, per output_frame).
std::string framesCsvLine(const localization::FrameReport& r, const SE3d& T);
/// The frame's pose covariance for the written pose `T` (lidar or body), in
/// geometry_msgs/PoseWithCovariance's convention (fusion::toReported).
Mat6d reportedCovariance(const localization::FrameReport& r, const SE3d& T);

/// Statistics of a run for summary.json.
struct RunSummary {
    std::string method;
    std::string status = "ok";  ///< "ok", or "failed": the run stopped on an error (exit code 1)
    std::string error;          ///< the one-line reason when it failed
    io::RawlogStats rawlog;     ///< what the rawlog reader read and skipped (e.g. empty scans)
    size_t frames = 0, diverged = 0, converged = 0, used_imu = 0;
    size_t with_prior = 0;               ///< frames whose solve had an odom_alt prior
    size_t recovered = 0;                ///< frames replaced by a verified relocalization
    std::array<size_t, 3> health{};      ///< frames ok, degraded, lost
    size_t flagged = 0;                  ///< frames with at least one degenerate axis
    size_t flagged_without_prior = 0;    ///< of those, frames solved without a prior
    std::array<size_t, 6> flagged_axis{};  ///< frames flagging x, y, z, roll, pitch, yaw
    double ms_median = 0, ms_p95 = 0, ms_mean = 0, fps = 0;  ///< wall time per frame
    double cpu_ms_median = 0;  ///< thread CPU time per frame
    localization::StageTimes stage_median;  ///< median per stage
    size_t map_points = 0;     ///< of the map the first frame used
    double map_prepare_s = 0;
    // A tiled map (doc/map.md "Tiled maps"): maps swapped in after the first, the largest map
    // loaded, the longest tile read + PriorMap preparation (in a thread) and the longest wait of
    // the frame loop for a map to be ready and swapped in.
    size_t map_reloads = 0;
    size_t map_points_max = 0;
    double map_reload_s_max = 0;
    double map_reload_wait_s_max = 0;
    // Against the rawlog's ground truth when it has one (frames matched by time).
    size_t gt_matched = 0;
    double ate_rmse = -1, ate_max = -1;  ///< [m], -1 when no ground truth
    /// The pose's largest std over the frames not lost (median, p95, max) [m] and [deg]; -1: none.
    std::array<double, 3> sigma_xyz{-1, -1, -1}, sigma_deg{-1, -1, -1};
};

/// summary.json's content (non-finite numbers left as they are: io::saveJson writes them as
/// null with a warning).
io::Json summaryJson(const RunSummary& s);

/// What summary.json says of the frames, gathered frame by frame: the counts go into the
/// summary at once, the rest is kept for fill() (each frame's stage times, its pose's largest
/// std, and its pose and the rawlog's GT for the ATE as 104-byte records: a 30-minute run keeps
/// 35 000 of them).
class RunTally {
   public:
    /// Counts the frame into s (frames, diverged, health, flagged axes...) and keeps its times,
    /// sigmas and written pose.
    void addFrame(const localization::FrameReport& r, const SE3d& T_written, RunSummary& s);
    void addGroundTruth(const PoseStamped& p);
    /// s's wall and CPU times, stage medians, pose sigmas (median, p95, max) and ATE against the
    /// ground truth (interpolated at each frame's time, gaps up to 1 s; no alignment), from the
    /// frames so far.
    void fill(RunSummary& s) const;

   private:
    struct KeptPose {
        double t = 0;
        Mat3d R = Mat3d::Identity();
        Vec3d p = Vec3d::Zero();
    };
    static Trajectory trajectoryOf(const std::vector<KeptPose>& kept);
    std::vector<double> ms_, cpu_, stage_[5], sigma_xyz_, sigma_deg_;
    std::vector<KeptPose> est_, gt_;
};

class RunOutputs {
   public:
    /// Creates DIR (and parents) and opens trajectory.tum and frames.csv. Throws
    /// std::runtime_error naming the path when it cannot. `report`: also write report.html.
    RunOutputs(const std::string& dir, double map_voxel, bool report = false);
    ~RunOutputs();

    void addFrame(const localization::FrameReport& r, const SE3d& T_written, const std::vector<Vec3f>& map_points);
    /// Writes summary.json and localized_map.pcd, and report.html when asked for; once, at the end
    /// (the map's points are handed to the file).
    void finish(const RunSummary& s);
    const std::string& dir() const { return dir_; }
    /// The report's data (its map, its inputs); nullptr when no report is written.
    RunReport* report() { return report_ ? &*report_ : nullptr; }

   private:
    std::string dir_;
    std::unique_ptr<io::TumWriter> tum_;
    std::ofstream csv_;
    std::ofstream cov_;  ///< trajectory_cov.txt
    float voxel_;
    VoxelSet occupied_;
    std::vector<Vec3f> map_;
    std::optional<RunReport> report_;
};

}  // namespace superloc::app
