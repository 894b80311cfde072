// Spinning multi-beam LiDAR model: each column fires from the pose at its own time.
//
// A sweep ending at t_end fires column c (c = 0..columns-1) at t_end - period + c*period/columns,
// at azimuth start_azimuth + rotation_sense * 360 deg * c / columns (lidar frame), all beams of
// a column at once. Points are given in the lidar frame *at their firing time* (as a real
// sensor does, so fast motion distorts the sweep), in firing order: column by column, beams
// from the top one down. This matches the per-point time the localizer derives from azimuth
// (doc/design.md#3-data-conventions; io::RawlogParams scan_period / rotation_sense / start_azimuth_deg defaults).
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/core/types.h>
#include <superloc/sim/raycaster.h>
#include <superloc/sim/trajectory.h>

#include <random>
#include <string>

namespace superloc::sim {

/// Section [lidar]: sensor intrinsics (usually from a preset in ini/sensors/) and mounting.
struct LidarParams : public mrpt::config::CLoadableOptions {
    std::string model = "os1-64";  ///< free text
    std::string preset;  ///< INI file (relative to the config) whose [lidar] is loaded first
    std::string label = "lidar";       ///< sensor label of the observations
    int beams = 64;                    ///< number of vertical channels
    double vfov_min_deg = -22.5;       ///< [deg] lowest beam elevation
    double vfov_max_deg = 22.5;        ///< [deg] highest beam elevation (beams evenly spaced)
    int columns = 1024;                ///< firings per revolution
    double rate_hz = 10.0;             ///< [Hz] revolutions per second
    double min_range = 0.3;            ///< [m]
    double max_range = 100.0;          ///< [m]
    double range_noise = 0.02;         ///< [m] 1-sigma Gaussian range noise
    double dropout_rate = 0.02;        ///< [0..1] probability that a return is lost
    double start_azimuth_deg = 180.0;  ///< [deg] azimuth of the first column
    int rotation_sense = 1;            ///< +1 counter-clockwise seen from above, -1 clockwise
    // Pose of the LiDAR in the IMU (body) frame: T_imu_lidar = the observation's sensorPose.
    double ext_x = 0.0, ext_y = 0.0, ext_z = 0.1;                 ///< [m]
    double ext_roll_deg = 0, ext_pitch_deg = 0, ext_yaw_deg = 0;  ///< [deg]
    // The platform's own body as a box in the LiDAR frame: rays into it return nothing (drivers
    // drop self-points). Disabled while any min >= max.
    double self_min_x = 0, self_min_y = 0, self_min_z = 0;  ///< [m]
    double self_max_x = 0, self_max_y = 0, self_max_z = 0;  ///< [m]

    double period() const { return 1.0 / rate_hz; }
    SE3d T_imu_lidar() const;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
};

/// Simulates one sweep ending at t_end (Scan::t = t_end, rel_time filled, T_imu_lidar set).
/// When `normals_map` is given it receives each point's surface normal (map frame).
Scan simulateSweep(const RayCaster& caster, const Mesh& mesh, const SmoothTrajectory& traj,
                   const LidarParams& p, double t_end, std::mt19937_64& rng,
                   std::vector<Vec3f>* normals_map = nullptr);

}  // namespace superloc::sim
