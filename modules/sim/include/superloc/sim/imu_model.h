// IMU model: exact specific force and angular rate of the trajectory, plus white noise and a
// bias random walk (continuous-time densities, as Kalibr / preintegration papers state them).
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/core/types.h>
#include <superloc/sim/trajectory.h>

#include <random>
#include <string>

namespace superloc::sim {

/// Section [imu]. Defaults: a common MEMS IMU (EuRoC's ADIS16448-like figures).
struct ImuParams : public mrpt::config::CLoadableOptions {
    std::string label = "imu";
    double rate_hz = 200.0;              ///< [Hz]
    double gravity = 9.81;               ///< [m/s^2] along -z of the map frame
    double acc_noise_density = 2.0e-3;   ///< [m/s^2/sqrt(Hz)] white noise
    double gyro_noise_density = 1.7e-4;  ///< [rad/s/sqrt(Hz)] white noise
    double acc_bias_rw = 3.0e-4;         ///< [m/s^3/sqrt(Hz)] bias random walk
    double gyro_bias_rw = 2.0e-5;        ///< [rad/s^2/sqrt(Hz)] bias random walk
    double acc_bias_init = 0.02;         ///< [m/s^2] 1-sigma of the initial bias per axis
    double gyro_bias_init = 0.002;       ///< [rad/s] 1-sigma of the initial bias per axis

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
};

/// Generates consecutive IMU samples; holds the evolving biases.
class ImuSimulator {
 public:
    ImuSimulator(const ImuParams& p, uint64_t seed);
    /// The sample at state s (call in time order, once per 1/rate_hz); biases then step on.
    ImuSample sample(const BodyState& s);
    /// Noise-free specific force and rate of a state (body frame).
    static ImuSample ideal(const BodyState& s, double gravity);

    const Vec3d& accBias() const { return ba_; }
    const Vec3d& gyroBias() const { return bg_; }

 private:
    ImuParams p_;
    std::mt19937_64 rng_;
    std::normal_distribution<double> n01_{0.0, 1.0};
    Vec3d ba_ = Vec3d::Zero(), bg_ = Vec3d::Zero();
    Vec3d gauss();
};

}  // namespace superloc::sim
