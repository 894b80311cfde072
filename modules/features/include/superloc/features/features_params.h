// Scan preprocessing parameters; section [features] of the INI.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace superloc::features {

struct FeaturesParams : public mrpt::config::CLoadableOptions {
    double min_range = 1.0;     ///< [m] points closer to the sensor are dropped (robot body)
    double max_range = 100.0;   ///< [m] points farther are dropped
    bool deskew = true;         ///< undo the motion during the sweep (needs per-point time)
    /// with IMU: deskew along the IMU's integrated trajectory over the sweep (false: one
    /// constant twist, the interval's mean rate and the predicted end velocity)
    bool deskew_imu_poses = true;
    /// without IMU, also deskew a frame whose prediction is the constant-velocity twist of the
    /// last two estimates, and estimate the sweep's velocity of a frame of unknown velocity; a
    /// frame predicted from odom_alt's motion is deskewed with it whatever this says (off: on the
    /// handheld office sequence it doubled the ATE, 0.14 vs 0.06 m)
    bool deskew_without_imu = false;
    double voxel_size = 0.5;    ///< [m] one candidate point per voxel of this size
    int max_features = 2000;    ///< cap on features per scan, taken evenly over the candidates
    /// classification of a neighbourhood from its PCA shape factors (see classify.h)
    double plane_max_thickness = 0.5;  ///< [-] l3/l2 below this: plane
    double line_min_linearity = 0.7;   ///< [-] linearity above this (and not a plane): line

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    /// Throws ConfigError naming [features] and the key when a value is out of range.
    void validate() const;
};

}  // namespace superloc::features
