// Section [eval] of the INI: the evaluation's tolerances and thresholds.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace superloc::eval {

struct EvalParams : public mrpt::config::CLoadableOptions {
    double assoc_tolerance = 0.02;    ///< [s] max |t_est - t_gt| to pair an estimate with GT
    bool align = false;               ///< SE(3) Umeyama alignment before ATE (no scale)
    double map_voxel = 0.05;          ///< [m] voxel of the localized map before comparing
    double outlier_threshold = 0.10;  ///< [m] a map point farther than this from GT is an outlier
    int robustness_bins = 100;        ///< bins of T in [0, 1] for Rp/Rr (tau = exp(-10 T))
    /// Risk as a failure predictor (riskPrediction): a frame fails along a translation axis
    /// when its error along that body axis exceeds risk_fail_xyz, along a rotation axis when
    /// the error rotation vector's component exceeds risk_fail_deg.
    double risk_fail_xyz = 0.10;      ///< [m]
    double risk_fail_deg = 1.0;       ///< [deg]

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    /// Throws ConfigError naming [eval] and the key.
    void validate() const;
};

}  // namespace superloc::eval
