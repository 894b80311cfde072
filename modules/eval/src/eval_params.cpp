#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/eval/eval_params.h>

#include <cmath>

namespace superloc::eval {

void EvalParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(assoc_tolerance, double, c, s);
    MRPT_LOAD_CONFIG_VAR(align, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(map_voxel, double, c, s);
    MRPT_LOAD_CONFIG_VAR(outlier_threshold, double, c, s);
    MRPT_LOAD_CONFIG_VAR(robustness_bins, int, c, s);
    MRPT_LOAD_CONFIG_VAR(risk_fail_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(risk_fail_deg, double, c, s);
}

void EvalParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(assoc_tolerance,
                                 "[s] max time difference to pair estimate and GT");
    MRPT_SAVE_CONFIG_VAR_COMMENT(align,
                                 "[bool] SE(3) Umeyama alignment before ATE (default: none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(map_voxel, "[m] voxel size of the localized map before comparing");
    MRPT_SAVE_CONFIG_VAR_COMMENT(outlier_threshold,
                                 "[m] map point farther than this from GT = outlier");
    MRPT_SAVE_CONFIG_VAR_COMMENT(robustness_bins,
                                 "[-] bins of T in [0,1] for Rp/Rr, tau = exp(-10 T)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(risk_fail_xyz, "[m] error along a body axis that counts as a failure (risk table)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(risk_fail_deg, "[deg] rotation error about a body axis that counts as a failure");
}

void EvalParams::validate() const {
    if (!(assoc_tolerance >= 0) || !std::isfinite(assoc_tolerance))
        throw ConfigError("[eval] assoc_tolerance must be a finite number >= 0 [s]");
    if (!(map_voxel >= 0) || !std::isfinite(map_voxel))
        throw ConfigError("[eval] map_voxel must be >= 0 [m] (0 = no voxel filter)");
    if (!(outlier_threshold > 0) || !std::isfinite(outlier_threshold))
        throw ConfigError("[eval] outlier_threshold must be > 0 [m]");
    if (!(risk_fail_xyz > 0) || !std::isfinite(risk_fail_xyz))
        throw ConfigError("[eval] risk_fail_xyz must be > 0 [m]");
    if (!(risk_fail_deg > 0) || !std::isfinite(risk_fail_deg))
        throw ConfigError("[eval] risk_fail_deg must be > 0 [deg]");
    if (robustness_bins < 1 || robustness_bins > 100000)
        throw ConfigError("[eval] robustness_bins must be in [1, 100000]");
}

}  // namespace superloc::eval
