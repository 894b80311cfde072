#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/sim/imu_model.h>

#include <cmath>

namespace superloc::sim {

void ImuParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(rate_hz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gravity, double, c, s);
    MRPT_LOAD_CONFIG_VAR(acc_noise_density, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gyro_noise_density, double, c, s);
    MRPT_LOAD_CONFIG_VAR(acc_bias_rw, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gyro_bias_rw, double, c, s);
    MRPT_LOAD_CONFIG_VAR(acc_bias_init, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gyro_bias_init, double, c, s);
}

void ImuParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(label, "sensor label of the observations");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rate_hz, "[Hz]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gravity, "[m/s^2] along -z of the map frame");
    MRPT_SAVE_CONFIG_VAR_COMMENT(acc_noise_density, "[m/s^2/sqrt(Hz)] white noise");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gyro_noise_density, "[rad/s/sqrt(Hz)] white noise");
    MRPT_SAVE_CONFIG_VAR_COMMENT(acc_bias_rw, "[m/s^3/sqrt(Hz)] bias random walk");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gyro_bias_rw, "[rad/s^2/sqrt(Hz)] bias random walk");
    MRPT_SAVE_CONFIG_VAR_COMMENT(acc_bias_init, "[m/s^2] 1-sigma initial bias per axis");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gyro_bias_init, "[rad/s] 1-sigma initial bias per axis");
}

void ImuParams::validate() const {
    if (!(rate_hz >= 10 && rate_hz <= 2000))
        throw ConfigError("[imu] rate_hz must be in [10, 2000]");
    if (!(gravity >= 0)) throw ConfigError("[imu] gravity must be >= 0");
    for (double v : {acc_noise_density, gyro_noise_density, acc_bias_rw, gyro_bias_rw,
                     acc_bias_init, gyro_bias_init})
        if (!(v >= 0)) throw ConfigError("[imu] noise densities and bias sigmas must be >= 0");
}

ImuSimulator::ImuSimulator(const ImuParams& p, uint64_t seed) : p_(p), rng_(seed) {
    ba_ = gauss() * p_.acc_bias_init;
    bg_ = gauss() * p_.gyro_bias_init;
}

Vec3d ImuSimulator::gauss() { return Vec3d(n01_(rng_), n01_(rng_), n01_(rng_)); }

ImuSample ImuSimulator::ideal(const BodyState& s, double gravity) {
    ImuSample m;
    m.t = s.t;
    // Specific force: f = R^T (a - g), g = (0, 0, -gravity).
    m.acc = s.T_map_body.linear().transpose() * (s.acc + Vec3d(0, 0, gravity));
    m.gyro = s.omega_body;
    return m;
}

ImuSample ImuSimulator::sample(const BodyState& s) {
    ImuSample m = ideal(s, p_.gravity);
    const double dt = 1.0 / p_.rate_hz;
    // Discrete white noise: sigma_d = density / sqrt(dt); bias walk: sigma_b = rw * sqrt(dt).
    const Vec3d na = gauss(), ng = gauss(), wa = gauss(), wg = gauss();
    m.acc += ba_ + na * (p_.acc_noise_density / std::sqrt(dt));
    m.gyro += bg_ + ng * (p_.gyro_noise_density / std::sqrt(dt));
    ba_ += wa * (p_.acc_bias_rw * std::sqrt(dt));
    bg_ += wg * (p_.gyro_bias_rw * std::sqrt(dt));
    return m;
}

}  // namespace superloc::sim
