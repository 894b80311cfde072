// IMU noise model and gravity; section [imu] of the INI.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace superloc::imu {

struct ImuParams : public mrpt::config::CLoadableOptions {
    double acc_noise = 0.02;       ///< [m/s^2/sqrt(Hz)] accelerometer white-noise density
    double gyro_noise = 0.002;     ///< [rad/s/sqrt(Hz)] gyroscope white-noise density
    double acc_bias_rw = 0.001;    ///< [m/s^3/sqrt(Hz)] accelerometer bias random walk
    double gyro_bias_rw = 0.0001;  ///< [rad/s^2/sqrt(Hz)] gyroscope bias random walk
    double gravity = 9.81;         ///< [m/s^2] magnitude; the map frame is z-up
    /// [s] at the start, samples within this window are used to initialise biases when at rest
    double init_window = 0.5;
    /// rest test: max std of |acc| [m/s^2] and max mean |gyro| [rad/s] over init_window
    double rest_acc_std = 0.1;
    double rest_gyro_max = 0.05;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    /// Throws ConfigError naming [imu] and the key when a value is out of range.
    void validate() const;
};

}  // namespace superloc::imu
