// Streaming rawlog reader and writer (MRPT observations-only format, gz; the
// action/sensory-frame format is tolerated on read). doc/design.md#3-data-conventions.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/core/types.h>

#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace mrpt::obs {
class CObservation;
}
namespace mrpt::system {
class COutputLogger;
}

namespace superloc::io {

/// Which observations mean what; section [rawlog] of the INI.
struct RawlogParams : public mrpt::config::CLoadableOptions {
    std::string odom_alt_label = "odom_alt";  ///< CObservationRobotPose label of the 2nd odometry
    std::string gt_label = "gt";              ///< CObservationRobotPose label of ground truth
    /// LiDAR sensor label to use; empty = every point-cloud/Velodyne/rotating-scan observation
    std::string lidar_label;
    /// IMU sensor label to use; empty = every CObservationIMU
    std::string imu_label;
    /// [s] observations may arrive out of order by up to this much; they are re-sorted in a
    /// window of this length (bounded memory). Anything older than the window is an error.
    double reorder_window = 0.5;
    /// Spinning-LiDAR per-point time from azimuth (for CObservationPointCloud, which has no time
    /// field): sweep period [s]; 0 disables (rel_time stays empty).
    double scan_period = 0.1;
    /// +1 counter-clockwise (seen from above, the usual Velodyne/Ouster sense), -1 clockwise
    int rotation_sense = 1;
    /// [deg] azimuth at which a sweep starts (the first firing)
    double start_azimuth_deg = 180.0;
    /// Which LiDAR scans to read, by their 0-based index in time order: `all`, `even`, `odd`,
    /// or `FIRST:END[:STEP]` (END exclusive, empty = to the end). The honest real-data protocol
    /// (doc/evaluation.md) maps one subset and localizes another, e.g. even -> odd.
    std::string scans = "all";

    /// The parsed `scans`: index i is read when i >= first, i < end and (i - first) % step == 0.
    struct ScanSelection {
        size_t first = 0, end = SIZE_MAX, step = 1;
        bool contains(size_t i) const { return i >= first && i < end && (i - first) % step == 0; }
    };
    /// Throws ConfigError naming [rawlog] scans when the text is not one of the forms above.
    ScanSelection scanSelection() const;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
};

/// One typed item of a rawlog.
struct RawlogItem {
    enum class Kind { Lidar, Imu, OdomAlt, GroundTruth };
    Kind kind = Kind::Lidar;
    std::variant<Scan, ImuSample, PoseStamped> data;

    double time() const;
    const Scan& scan() const { return std::get<Scan>(data); }
    const ImuSample& imu() const { return std::get<ImuSample>(data); }
    const PoseStamped& pose() const { return std::get<PoseStamped>(data); }
};

/// Counters of what the reader saw; non-fatal anomalies are counted here and logged once.
struct RawlogStats {
    size_t lidar = 0, imu = 0, odom_alt = 0, gt = 0;
    size_t unknown_observations = 0;  ///< observation classes SuperLoc does not use (skipped)
    size_t other_pose_labels = 0;     ///< CObservationRobotPose with a label not configured
    size_t invalid_points = 0;        ///< NaN/inf points dropped from scans
    size_t empty_scans = 0;           ///< LiDAR observations with no valid point (skipped)
    size_t invalid_imu = 0;           ///< IMU samples without acc+gyro or with NaN (skipped)
    size_t skipped_labels = 0;        ///< LiDAR/IMU observations of a non-configured label
    size_t unselected_scans = 0;      ///< LiDAR scans left out by [rawlog] scans
    size_t max_pending = 0;           ///< most items held at once in the re-sort window
    std::vector<std::string> other_lidar_labels;  ///< labels of the LiDAR scans lidar_label left out (first few)
};

/// Streams a rawlog in timestamp order, one typed item at a time. Memory is bounded by the
/// reorder window, not by the file length.
///
/// Scans: Scan::t is the observation timestamp; points are in the sensor frame and
/// T_imu_lidar is the observation's sensorPose. Per-point rel_time (relative to Scan::t):
///  - CObservationPointCloud: from the azimuth (RawlogParams scan_period, rotation_sense,
///    start_azimuth_deg) for a sweep that *ends* at t: rel_time in [-scan_period, 0).
///  - CObservationVelodyneScan: MRPT's per-point timestamps; MRPT stamps the observation at the
///    *first* firing, so rel_time is in [0, sweep) (>= 0). Without raw packets, its stored
///    `point_cloud` is used as it is (RawlogWriter::writeTimedScan: rel_time = point time -
///    observation time, any sign).
///  - CObservationRotatingScan (VLP-16 / HDL-32E range images as MRPT 2.5.8's fromVelodyne()
///    writes them, or 1-row 2-D scans): from the column, also >= 0. Other models carry no beam
///    angles in MRPT 2.5.8 and are skipped (counted in unknown_observations).
/// Intensity: as stored (CPointsMapXYZI), or 0..1 for Velodyne/rotating scans (byte / 255). Throws
/// std::runtime_error with a one-line message naming the file (and the entry index) on a missing,
/// truncated or corrupt file, or on timestamps going backwards by more than the reorder window.
/// The error comes after every item read before it: the items still held in the re-sort window
/// are returned first (a rawlog cut inside its 10th scan gives 9 scans, then the error).
class RawlogReader {
 public:
    explicit RawlogReader(const std::string& path, const RawlogParams& params = {});
    ~RawlogReader();
    RawlogReader(const RawlogReader&) = delete;
    RawlogReader& operator=(const RawlogReader&) = delete;

    /// Next item in time order; false at the end of the file.
    bool next(RawlogItem& item);

    const RawlogStats& stats() const;
    const std::string& path() const;
    /// Why the reader returned no LiDAR scan, as one line naming the file and the culprit
    /// ([rawlog] lidar_label, [rawlog] scans, empty scans), for a caller that needs one.
    std::string noScanReason() const;
    /// The logger of the (once-per-kind) warnings, e.g. to lower its verbosity for --quiet.
    mrpt::system::COutputLogger& logger();

 private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Writes a rawlog (observations-only format, gz-compressed), readable by `rawlog-edit --info`.
class RawlogWriter {
 public:
    explicit RawlogWriter(const std::string& path);
    ~RawlogWriter();
    RawlogWriter(const RawlogWriter&) = delete;
    RawlogWriter& operator=(const RawlogWriter&) = delete;

    /// As a CObservationPointCloud holding a CPointsMapXYZI; sensorPose = scan.T_imu_lidar.
    void writeScan(const Scan& scan, const std::string& label = "lidar");
    /// A scan with measured per-point time (scan.rel_time, one per point): as a
    /// CObservationVelodyneScan without packets whose `point_cloud` holds x, y, z, intensity
    /// (a byte: 255 * clamp(intensity / intensity_max, 0, 1)) and each point's absolute
    /// timestamp t + rel_time (MRPT clock, 100 ns). CPointsMapXYZI has no time field; this is
    /// MRPT 2.5.8's one point-cloud observation that keeps per-point time (doc/io.md).
    /// Throws when rel_time does not have one entry per point.
    void writeTimedScan(const Scan& scan, const std::string& label = "lidar",
                        float intensity_max = 255.0f);
    /// As a CObservationIMU (IMU_X_ACC.., IMU_WX..).
    void writeImu(const ImuSample& imu, const std::string& label = "imu");
    /// As a CObservationRobotPose (pose + covariance, identity*1e-6 when none) with `label`.
    void writePose(const PoseStamped& pose, const std::string& label);
    /// Any MRPT observation as it is.
    void write(const mrpt::obs::CObservation& obs);
    void close();

 private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace superloc::io
