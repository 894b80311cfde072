// Active sensor fusion (paper §III-C, doc/method.md §2): the information of the relative-pose prior
// from the alignment risk, and the two comparison variants of doc/design.md#6-method-variants.
//
//   superloc:    W = diag(max(0, 1 - gamma_k) * s_k)        (paper: Cov_prior = I - Sigma_cov)
//                s_k = tr(H_group) / 3, H = scan information in body coordinates (doc/method.md §2)
//   passive:     W = diag(1/sigma_xyz^2 (x3), 1/sigma_rot^2 (x3)), always on
//   eigen_remap: Zhang et al. 2016 solution remapping: the update is projected onto the
//                eigenvectors of H whose eigenvalue is above a threshold; the reference pose
//                (odom_alt or the prediction) supplies the rest.
//
// All 6-vectors in (x y z roll pitch yaw) order, body (right-perturbation) coordinates: a pose
// T perturbed by d is T * Exp(d), the convention of RelativePoseFactor's residual.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/core/types.h>
#include <superloc/fusion/scan_factor.h>

#include <string>
#include <vector>

namespace superloc::fusion {

/// Keys of section [fusion] for the prior of the active-fusion methods.
struct ActiveFusionParams : public mrpt::config::CLoadableOptions {
    double prior_scale = 1.0;  ///< [-] multiplies s_k (superloc)
    /// superloc: s_k is capped by odom_alt's own information over the frame, 1 / sigma_k^2 with
    /// sigma_k the growth of its reported std between the two scan times (when it reports one)
    bool prior_cap_by_odom_cov = true;
    double odom_sigma_min_xyz = 0.001;     ///< [m] floor of that sigma (translation)
    double odom_sigma_min_rot_deg = 0.01;  ///< [deg] floor of that sigma (rotation)
    double passive_sigma_xyz = 0.02;       ///< [m] per-frame std of the passive prior's translation
    double passive_sigma_rot_deg = 0.2;    ///< [deg] per-frame std of its rotation
    /// [-] eigen_remap: an eigen-direction of the scan Hessian's translation or rotation block
    /// whose share of the block's trace is below this is degenerate (a uniform spread gives 1/3;
    /// the default, 0.2 / 3, is the share below which the risk's gamma < 0.2 rule flags an axis)
    double eigen_threshold = 0.2 / 3.0;
    /// Robust loss on the odom_alt relative-pose prior (superloc and passive alike): `none`,
    /// `huber` or `cauchy` (the scan's robust_kernel names) as a Ceres loss on its whitened
    /// residual, scale prior_kernel_sigmas (in the prior's own standard deviations). A jump of
    /// odom_alt that its covariance does not report is then a many-sigma outlier against the
    /// IMU / scan evidence, and pulls with a bounded, falling force instead of in full
    /// (doc/method.md §2).
    /// superloc: odom_alt's systematic error (drift per metre, rotation scale, rotation per
    /// metre) fitted online on the axes the scan holds and removed before fusing
    /// (fusion::OdomCalibration, doc/method.md §2)
    bool odom_calibration = true;
    double calibration_memory_m = 500.0;  ///< [m] forgetting distance of that fit
    /// [-] superloc and the pose covariance: the estimate's information (EstimateInformation)
    /// carries the IMU chain with [imu]'s noise densities and bias walks times this. The solver
    /// keeps [imu]'s own, inflated for robustness; this makes the estimate's std along a blind
    /// axis the error the IMU chain really makes (doc/method.md §2, "The estimate's own sigma")
    double estimate_imu_scale = 0.5;
    /// The reported pose's covariance (fusion::PosePosterior, doc/method.md §4): a floor per axis
    /// for the errors all of a frame's residuals share (map, deskew, timing)
    double cov_floor_xyz = 0.01;    ///< [m]
    double cov_floor_deg = 0.02;    ///< [deg]
    /// [m] the position's floor where the sweep was deskewed along the IMU's trajectory: no
    /// deskew or timing error left for every residual to share, the map's remains
    double cov_floor_imu_xyz = 0.007;
    /// [m] the prior map's error that is coherent over a scan's footprint (a warp, a mapping
    /// run's misalignment): it turns the pose about body axis k by cov_map_xyz / r_k, r_k the
    /// scan's lever arm about k (fusion::mapRotationFloor); 0: no such floor
    double cov_map_xyz = 0.005;
    /// [m] the prior map's error as a smooth random field (fusion::mapErrorShare): its
    /// correlation length. The position's map floor (cov_floor_imu_xyz) is then the share of the
    /// field the scan's footprint takes, not all of it on every axis; 0: all of it (the constant
    /// floor)
    double cov_map_length = 10.0;
    /// [m] the grid the scan's correspondences are summed on for that share (doubled where a
    /// scan spans more than fusion::kMapShareMaxCells cells)
    double cov_map_cell = 4.0;
    /// [deg] how well the direction a carried position drifts along is known: the scan's
    /// linearized free direction, which the map's tilted normals turn by about this against the
    /// direction the pose really drifts along (the axis of motion). The position's covariance
    /// takes (sin(this) x its largest std)^2 across that direction (fusion::driftTiltCovariance,
    /// doc/method.md §4 "The drift's direction"); 0: none
    double cov_drift_tilt_deg = 0.5;
    std::string prior_kernel = "cauchy";
    double prior_kernel_sigmas = 10.0;  ///< [-] Cauchy scale, in sigmas of the prior

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    /// Throws ConfigError naming [fusion] and the key when a value is out of range.
    void validate() const;
};

/// Information of the scan residuals w.r.t. a body perturbation of T_map_imu:
/// H = sum_i w_i / sigma^2 J_i^T J_i (the Gauss-Newton Hessian of paper eq. 1 / 12's scan term).
/// w_i = fit weight * robust weight when `sqrt_w` (ScanFactor::sqrtWeights, squared) is given,
/// else the fit weight alone.
Mat6d scanInformation(const std::vector<Correspondence>& corr, const SE3d& T_map_imu,
                      double sigma, const std::vector<double>* sqrt_w = nullptr);

/// s_k = tr(H_tt) / 3 for x, y, z and tr(H_rr) / 3 for roll, pitch, yaw: the mean information
/// one axis of the group receives from the scan.
Vec6d priorScale(const Mat6d& H);

/// Per-frame std of odom_alt from the covariances it reports at the two scan times: the growth
/// of the std, sqrt(cov1_kk) - sqrt(cov0_kk) (the simulator's covariance is an accumulated
/// drift bound), floored by the INI minimums.
Vec6d odomIncrementSigma(const Mat6d& cov0, const Mat6d& cov1, const ActiveFusionParams& p);

/// The same growth read as an error that keeps its sign (a std that grows with the distance is a
/// drift's, not a sum of independent steps): a frame of `d` metres at `since_m[k]` metres since
/// the scan last held translation axis k gets sqrt(V(D + d) - V(D)), V(D) = (rate D)^2 with
/// rate = growth / d, i.e. growth * sqrt(1 + 2 D / d); floored as above. Rotation axes (their
/// reported std grows with the angle turned, not tracked since held) are as odomIncrementSigma.
Vec6d odomIncrementSigmaKeepingSign(const Mat6d& cov0, const Mat6d& cov1, const ActiveFusionParams& p,
                                    double d, const Vec6d& since_m);

/// s_k capped by 1 / sigma_k^2.
Vec6d capScale(const Vec6d& s, const Vec6d& sigma);

/// W_k = max(0, 1 - gamma_k) * s_k (doc/method.md §2; paper Cov_prior = I - Sigma_cov read as weight).
Vec6d activeInformation(const Vec6d& gamma, const Vec6d& s);

/// The passive prior's constant information (diagonal).
Vec6d passiveInformation(const ActiveFusionParams& p);

/// sqrt of a diagonal information, as RelativePoseFactor's 6x6 sqrt_info.
Mat6d sqrtInfo(const Vec6d& W);
/// The same for a full symmetric positive semi-definite information (L^T L = W).
Mat6d sqrtInfo(const Mat6d& W);

struct RemapResult {
    SE3d T = SE3d::Identity();          ///< remapped pose
    int removed = 0;                    ///< eigen-directions below the threshold
    Vec6d prior_share = Vec6d::Zero();  ///< diag of the projector onto the removed subspace
};

/// Zhang et al. 2016 solution remapping, per group: d = Log(T_ref^-1 T_solved) (toVec6) is
/// projected onto the eigenvectors of H's translation block and of its rotation block (each
/// divided by its trace: eigenvalues are shares of the group's information, 1/3 each for a
/// uniform spread) whose share is >= threshold: T = T_ref Exp(V_f V_f^T d). A group with no
/// information (trace 0) is removed whole. Cross terms between the groups are not used.
RemapResult eigenRemap(const SE3d& T_ref, const SE3d& T_solved, const Mat6d& H, double threshold);

}  // namespace superloc::fusion
