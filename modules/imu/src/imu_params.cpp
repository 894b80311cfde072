#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/imu/imu_params.h>

namespace superloc::imu {

void ImuParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(acc_noise, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gyro_noise, double, c, s);
    MRPT_LOAD_CONFIG_VAR(acc_bias_rw, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gyro_bias_rw, double, c, s);
    MRPT_LOAD_CONFIG_VAR(gravity, double, c, s);
    MRPT_LOAD_CONFIG_VAR(init_window, double, c, s);
    MRPT_LOAD_CONFIG_VAR(rest_acc_std, double, c, s);
    MRPT_LOAD_CONFIG_VAR(rest_gyro_max, double, c, s);
}

void ImuParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(acc_noise, "[m/s^2/sqrt(Hz)] accelerometer noise density");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gyro_noise, "[rad/s/sqrt(Hz)] gyroscope noise density");
    MRPT_SAVE_CONFIG_VAR_COMMENT(acc_bias_rw, "[m/s^3/sqrt(Hz)] accelerometer bias random walk");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gyro_bias_rw, "[rad/s^2/sqrt(Hz)] gyroscope bias random walk");
    MRPT_SAVE_CONFIG_VAR_COMMENT(gravity, "[m/s^2] gravity magnitude (map frame is z-up)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(init_window, "[s] start window used for rest initialisation");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rest_acc_std, "[m/s^2] at rest: max std of |acc| in the window");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rest_gyro_max, "[rad/s] at rest: max mean |gyro| in the window");
}

void ImuParams::validate() const {
    const auto positive = [](double v, const char* key) {
        if (!(v > 0)) throw ConfigError(std::string("[imu] ") + key + " must be > 0");
    };
    positive(acc_noise, "acc_noise");
    positive(gyro_noise, "gyro_noise");
    positive(acc_bias_rw, "acc_bias_rw");
    positive(gyro_bias_rw, "gyro_bias_rw");
    positive(gravity, "gravity");
    if (init_window < 0) throw ConfigError("[imu] init_window must be >= 0");
    positive(rest_acc_std, "rest_acc_std");
    positive(rest_gyro_max, "rest_gyro_max");
}

}  // namespace superloc::imu
