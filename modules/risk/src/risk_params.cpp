#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/risk/alignment_risk.h>

#include <cmath>

namespace superloc::risk {

void RiskParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(degenerate_threshold, double, c, s);
    MRPT_LOAD_CONFIG_VAR(weak_sigma_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(weak_sigma_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(normal_noise_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(weighted_labels, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(rotation_labels, int, c, s);
    MRPT_LOAD_CONFIG_VAR(keep_jacobians, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(hessian_eigen, bool, c, s);
}

void RiskParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        degenerate_threshold,
        "[-] an axis with confidence gamma below this is degenerate (paper: 0.2)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(weak_sigma_xyz,
                                 "[m] the estimate (scan + IMU, without odom_alt) is weak along an axis whose std exceeds this");
    MRPT_SAVE_CONFIG_VAR_COMMENT(weak_sigma_deg, "[deg] the same for a rotation axis");
    MRPT_SAVE_CONFIG_VAR_COMMENT(normal_noise_deg,
                                 "[deg] map normal noise: the scan's information below sin^2 of it (a share) holds nothing");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        weighted_labels, "[bool] a label counts its correspondence's fit weight instead of 1");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        rotation_labels,
        "[1|2] rotation labels per correspondence: 1 = largest torque axis, 2 = two largest");
    MRPT_SAVE_CONFIG_VAR_COMMENT(keep_jacobians,
                                 "[bool] keep the per-correspondence Jacobian rows in the report");
    MRPT_SAVE_CONFIG_VAR_COMMENT(
        hessian_eigen, "[bool] also compute the classic Hessian eigenvalues (comparison only)");
}

void RiskParams::validate() const {
    if (!std::isfinite(degenerate_threshold) || degenerate_threshold < 0 ||
        degenerate_threshold > 1)
        throw ConfigError("[risk] degenerate_threshold = " + std::to_string(degenerate_threshold) +
                          " must be in [0, 1] (gamma is a ratio in [0, 1]; the paper uses 0.2)");
    if (!(weak_sigma_xyz > 0 && std::isfinite(weak_sigma_xyz)))
        throw ConfigError("[risk] weak_sigma_xyz must be a finite value > 0 [m]");
    if (!(weak_sigma_deg > 0 && std::isfinite(weak_sigma_deg)))
        throw ConfigError("[risk] weak_sigma_deg must be a finite value > 0 [deg]");
    if (!(normal_noise_deg >= 0 && normal_noise_deg < 45))
        throw ConfigError("[risk] normal_noise_deg must be in [0, 45) [deg]");
    if (rotation_labels != 1 && rotation_labels != 2)
        throw ConfigError("[risk] rotation_labels = " + std::to_string(rotation_labels) +
                          " must be 1 or 2");
}

}  // namespace superloc::risk
