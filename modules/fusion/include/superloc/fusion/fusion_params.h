// Parameters of the per-frame Ceres problem; section [fusion] of the INI.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/fusion/prior_weight.h>

#include <string>

namespace superloc::fusion {

struct FusionParams : public mrpt::config::CLoadableOptions {
    double scan_sigma = 0.05;          ///< [m] std of a scan residual (point-to-plane distance)
    std::string robust_kernel = "cauchy";  ///< none | huber | cauchy (applied as IRLS weights)
    double kernel_scale = 0.1;         ///< [m] scale of the robust kernel
    int max_iterations = 8;            ///< Ceres iterations per solve (one solve per association)
    /// Two-state window (only with IMU): the previous frame's state is optimised too, held by
    /// a prior: `marginalized` = the last solve's marginal of that state (full information,
    /// correlations included, scaled by marginal_scale; doc/method.md §3), `fixed` = the
    /// sigmas below. The sigmas also hold the first state, and any state whose marginal is
    /// not available (the frame's pose did not come from its own solve).
    std::string window = "marginalized";
    double marginal_scale = 1.0;  ///< [-] factor on the marginal's information (< 1 = less sure)
    double prev_pose_sigma_xyz = 0.02;      ///< [m]
    double prev_pose_sigma_rot_deg = 0.2;   ///< [deg]
    double prev_velocity_sigma = 0.5;       ///< [m/s]
    double prev_acc_bias_sigma = 0.05;      ///< [m/s^2]
    double prev_gyro_bias_sigma = 0.002;    ///< [rad/s]
    /// Prior of the active-fusion methods (superloc, passive, eigen_remap), same section.
    ActiveFusionParams active;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    /// Throws ConfigError naming [fusion] and the key when a value is out of range.
    void validate() const;
};

}  // namespace superloc::fusion
