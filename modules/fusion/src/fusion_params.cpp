#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/fusion/fusion_params.h>
#include <superloc/fusion/scan_factor.h>

namespace superloc::fusion {

void FusionParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(scan_sigma, double, c, s);
    robust_kernel = c.read_string(s, "robust_kernel", robust_kernel);
    MRPT_LOAD_CONFIG_VAR(kernel_scale, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_iterations, int, c, s);
    window = c.read_string(s, "window", window);
    MRPT_LOAD_CONFIG_VAR(marginal_scale, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prev_pose_sigma_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prev_pose_sigma_rot_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prev_velocity_sigma, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prev_acc_bias_sigma, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prev_gyro_bias_sigma, double, c, s);
    active.loadFromConfigFile(c, s);
}

void FusionParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(scan_sigma, "[m] std of one scan residual");
    MRPT_SAVE_CONFIG_VAR_COMMENT(robust_kernel, "none | huber | cauchy");
    MRPT_SAVE_CONFIG_VAR_COMMENT(kernel_scale, "[m] robust kernel scale");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_iterations, "Ceres iterations per solve");
    MRPT_SAVE_CONFIG_VAR_COMMENT(window, "IMU window prior on the previous state: marginalized | fixed");
    MRPT_SAVE_CONFIG_VAR_COMMENT(marginal_scale, "[-] factor on the marginal's information");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prev_pose_sigma_xyz, "[m] prior on the previous pose (IMU window)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prev_pose_sigma_rot_deg, "[deg] prior on the previous attitude");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prev_velocity_sigma, "[m/s] prior on the previous velocity");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prev_acc_bias_sigma, "[m/s^2] prior on the previous acc bias");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prev_gyro_bias_sigma, "[rad/s] prior on the previous gyro bias");
    active.saveToConfigFile(c, s);
}

void FusionParams::validate() const {
    const auto positive = [](double v, const char* key) {
        if (!(v > 0)) throw ConfigError(std::string("[fusion] ") + key + " must be > 0");
    };
    positive(scan_sigma, "scan_sigma");
    positive(kernel_scale, "kernel_scale");
    if (max_iterations < 1) throw ConfigError("[fusion] max_iterations must be >= 1");
    if (window != "marginalized" && window != "fixed")
        throw ConfigError("[fusion] window = '" + window + "' (use marginalized or fixed)");
    positive(marginal_scale, "marginal_scale");
    positive(prev_pose_sigma_xyz, "prev_pose_sigma_xyz");
    positive(prev_pose_sigma_rot_deg, "prev_pose_sigma_rot_deg");
    positive(prev_velocity_sigma, "prev_velocity_sigma");
    positive(prev_acc_bias_sigma, "prev_acc_bias_sigma");
    positive(prev_gyro_bias_sigma, "prev_gyro_bias_sigma");
    active.validate();
    try {
        robustKernelFromString(robust_kernel);
    } catch (const std::exception& e) {
        throw ConfigError(std::string("[fusion] robust_kernel: ") + e.what());
    }
}

}  // namespace superloc::fusion
