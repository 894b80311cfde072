#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/fusion/prior_weight.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace superloc::fusion {

void ActiveFusionParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                            const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(prior_scale, double, c, s);
    MRPT_LOAD_CONFIG_VAR(prior_cap_by_odom_cov, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(odom_sigma_min_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(odom_sigma_min_rot_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(passive_sigma_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(passive_sigma_rot_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(eigen_threshold, double, c, s);
    MRPT_LOAD_CONFIG_VAR(odom_calibration, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(calibration_memory_m, double, c, s);
    MRPT_LOAD_CONFIG_VAR(estimate_imu_scale, double, c, s);
    MRPT_LOAD_CONFIG_VAR(cov_floor_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(cov_floor_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(cov_floor_imu_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(cov_map_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(cov_map_length, double, c, s);
    MRPT_LOAD_CONFIG_VAR(cov_map_cell, double, c, s);
    MRPT_LOAD_CONFIG_VAR(cov_drift_tilt_deg, double, c, s);
    prior_kernel = c.read_string(s, "prior_kernel", prior_kernel);
    MRPT_LOAD_CONFIG_VAR(prior_kernel_sigmas, double, c, s);
}

void ActiveFusionParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                          const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(prior_scale, "[-] superloc: multiplies s_k of W = (1-gamma) s");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prior_cap_by_odom_cov,
                                 "superloc: cap s_k by odom_alt's reported per-frame information");
    MRPT_SAVE_CONFIG_VAR_COMMENT(odom_sigma_min_xyz, "[m] floor of odom_alt's per-frame std");
    MRPT_SAVE_CONFIG_VAR_COMMENT(odom_sigma_min_rot_deg, "[deg] floor of its rotation std");
    MRPT_SAVE_CONFIG_VAR_COMMENT(passive_sigma_xyz, "[m] passive: per-frame prior std");
    MRPT_SAVE_CONFIG_VAR_COMMENT(passive_sigma_rot_deg, "[deg] passive: per-frame prior std");
    MRPT_SAVE_CONFIG_VAR_COMMENT(eigen_threshold, "[-] eigen_remap: min share of a group's information (uniform 1/3)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(odom_calibration, "superloc: learn odom_alt's systematic error where the scan holds an axis");
    MRPT_SAVE_CONFIG_VAR_COMMENT(calibration_memory_m, "[m] superloc: forgetting distance of that fit");
    MRPT_SAVE_CONFIG_VAR_COMMENT(cov_floor_xyz, "[m] the reported pose's covariance: std floor per axis (map, deskew, timing)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(cov_floor_deg, "[deg] ... and per rotation axis");
    MRPT_SAVE_CONFIG_VAR_COMMENT(cov_floor_imu_xyz, "[m] the position's std floor where the sweep was deskewed along the IMU (map only)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(cov_map_xyz, "[m] the prior map's error coherent over a scan: rotation std floor about axis k = this / the scan's lever arm about k");
    MRPT_SAVE_CONFIG_VAR_COMMENT(cov_map_length, "[m] the map's error field's correlation length: the position's map floor is the share the scan's footprint takes of it (0: all of it, the constant floor)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(cov_map_cell, "[m] the grid the scan's correspondences are summed on for that share (coarser where a scan spans more than 64 cells)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(cov_drift_tilt_deg, "[deg] the covariance's free direction is known to this: across it the position takes sin(this) x its std there");
    MRPT_SAVE_CONFIG_VAR_COMMENT(estimate_imu_scale, "[-] the estimate's IMU noise and bias walks = [imu]'s x this (the solver keeps [imu]'s)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prior_kernel, "robust loss on the odom_alt prior: none | huber | cauchy");
    MRPT_SAVE_CONFIG_VAR_COMMENT(prior_kernel_sigmas, "[-] its scale, in sigmas of the prior");
}

void ActiveFusionParams::validate() const {
    const auto positive = [](double v, const char* key) {
        if (!(v > 0)) throw ConfigError(std::string("[fusion] ") + key + " must be > 0");
    };
    if (!(prior_scale >= 0)) throw ConfigError("[fusion] prior_scale must be >= 0");
    positive(passive_sigma_xyz, "passive_sigma_xyz");
    positive(passive_sigma_rot_deg, "passive_sigma_rot_deg");
    if (!(eigen_threshold >= 0)) throw ConfigError("[fusion] eigen_threshold must be >= 0");
    positive(odom_sigma_min_xyz, "odom_sigma_min_xyz");
    positive(odom_sigma_min_rot_deg, "odom_sigma_min_rot_deg");
    try {
        robustKernelFromString(prior_kernel);
    } catch (const std::exception& e) {
        throw ConfigError(std::string("[fusion] prior_kernel: ") + e.what());
    }
    positive(prior_kernel_sigmas, "prior_kernel_sigmas");
    positive(calibration_memory_m, "calibration_memory_m");
    positive(estimate_imu_scale, "estimate_imu_scale");
    if (!(cov_floor_xyz >= 0 && cov_floor_deg >= 0 && std::isfinite(cov_floor_xyz + cov_floor_deg)))
        throw ConfigError("[fusion] cov_floor_xyz and cov_floor_deg must be finite and >= 0");
    if (!(cov_floor_imu_xyz >= 0 && std::isfinite(cov_floor_imu_xyz)))
        throw ConfigError("[fusion] cov_floor_imu_xyz must be finite and >= 0");
    if (!(cov_map_xyz >= 0 && std::isfinite(cov_map_xyz)))
        throw ConfigError("[fusion] cov_map_xyz must be finite and >= 0");
    if (!(cov_map_length >= 0 && std::isfinite(cov_map_length)))
        throw ConfigError("[fusion] cov_map_length must be finite and >= 0");
    if (!(cov_map_cell > 0 && std::isfinite(cov_map_cell))) throw ConfigError("[fusion] cov_map_cell must be finite and > 0");
    if (!(cov_drift_tilt_deg >= 0 && cov_drift_tilt_deg < 45))
        throw ConfigError("[fusion] cov_drift_tilt_deg must be in [0, 45)");
}

Mat6d scanInformation(const std::vector<Correspondence>& corr, const SE3d& T, double sigma,
                      const std::vector<double>* sqrt_w) {
    // The scan factor's analytic Jacobian is w.r.t. PoseManifold's [dt (map), dtheta (body)];
    // a body perturbation T Exp([u; dtheta]) moves the translation by R u, so J_body = J [R 0; 0
    // I].
    const Mat3d R = T.linear();
    // Two passes per block of correspondences: their rows first, then the sums. Rows written one
    // scalar at a time and read at once as packed pairs stalled on store forwarding; a block later
    // the stores have retired. The same products and sums in the same order, so the same bits.
    constexpr size_t kBlock = 64;
    double J[kBlock][18], w[kBlock];
    int d[kBlock];
    Mat6d H = Mat6d::Zero();
    for (size_t b = 0; b < corr.size(); b += kBlock) {
        const size_t m = std::min(kBlock, corr.size() - b);
        for (size_t j = 0; j < m; ++j) {
            const size_t i = b + j;
            w[j] = sqrt_w && i < sqrt_w->size() ? (*sqrt_w)[i] * (*sqrt_w)[i]
                                                : std::max(0.0, corr[i].weight);
            d[j] = w[j] > 0 ? correspondenceBodyJacobian(corr[i], R, J[j]) : 0;
        }
        for (size_t j = 0; j < m; ++j)
            for (int k = 0; k < d[j]; ++k) {
                const Eigen::Map<const Vec6d> row(J[j] + 6 * k);
                H.noalias() += w[j] * row * row.transpose();
            }
    }
    return H / (sigma * sigma);
}

Vec6d priorScale(const Mat6d& H) {
    Vec6d s;
    s.head<3>().setConstant(H.topLeftCorner<3, 3>().trace() / 3.0);
    s.tail<3>().setConstant(H.bottomRightCorner<3, 3>().trace() / 3.0);
    return s;
}

namespace {
/// The growth of a reported std on axis k between two covariances (may be negative or NaN).
double stdGrowth(const Mat6d& cov0, const Mat6d& cov1, int k) {
    return std::sqrt(std::max(0.0, cov1(k, k))) - std::sqrt(std::max(0.0, cov0(k, k)));
}
}  // namespace

Vec6d odomIncrementSigma(const Mat6d& cov0, const Mat6d& cov1, const ActiveFusionParams& p) {
    Vec6d sigma;
    for (int k = 0; k < 6; ++k) {
        const double floor = k < 3 ? p.odom_sigma_min_xyz : p.odom_sigma_min_rot_deg * M_PI / 180.0;
        const double grow = stdGrowth(cov0, cov1, k);
        sigma[k] = std::max(floor, std::isfinite(grow) ? grow : floor);
    }
    return sigma;
}

Vec6d odomIncrementSigmaKeepingSign(const Mat6d& cov0, const Mat6d& cov1, const ActiveFusionParams& p,
                                    double d, const Vec6d& since_m) {
    Vec6d sigma = odomIncrementSigma(cov0, cov1, p);
    if (!(d > 1e-9) || !std::isfinite(d)) return sigma;
    for (int k = 0; k < 3; ++k) {
        const double grow = stdGrowth(cov0, cov1, k);
        const double D = std::isfinite(since_m[k]) ? std::max(0.0, since_m[k]) : 0.0;
        if (std::isfinite(grow) && grow > 0)
            sigma[k] = std::max(p.odom_sigma_min_xyz, grow * std::sqrt(1.0 + 2.0 * D / d));
    }
    return sigma;
}

Vec6d capScale(const Vec6d& s, const Vec6d& sigma) {
    Vec6d out;
    for (int k = 0; k < 6; ++k) out[k] = std::min(s[k], 1.0 / (sigma[k] * sigma[k]));
    return out;
}

Vec6d activeInformation(const Vec6d& gamma, const Vec6d& s) {
    // doc/method.md §2: W = diag(max(0, 1 - gamma_k)) s_k.
    Vec6d W;
    for (int k = 0; k < 6; ++k) W[k] = std::max(0.0, 1.0 - gamma[k]) * std::max(0.0, s[k]);
    return W;
}

Vec6d passiveInformation(const ActiveFusionParams& p) {
    const double st = p.passive_sigma_xyz, sr = p.passive_sigma_rot_deg * M_PI / 180.0;
    Vec6d W;
    W << Vec3d::Constant(1.0 / (st * st)), Vec3d::Constant(1.0 / (sr * sr));
    return W;
}

Mat6d sqrtInfo(const Vec6d& W) {
    Mat6d S = Mat6d::Zero();
    for (int k = 0; k < 6; ++k) S(k, k) = std::sqrt(std::max(0.0, W[k]));
    return S;
}

Mat6d sqrtInfo(const Mat6d& W) {
    const Eigen::SelfAdjointEigenSolver<Mat6d> es(0.5 * (W + W.transpose()));
    return es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
}

RemapResult eigenRemap(const SE3d& T_ref, const SE3d& T_solved, const Mat6d& H, double threshold) {
    // Zhang, Kaess, Singh 2016, eq. (8)-(10): x_f = V_f^-1 V_u x_u, with V the eigenvectors of
    // the (symmetric) Hessian as rows and V_f = V with the rows of eigenvalues below the
    // threshold zeroed; V orthonormal gives x_f = V^T diag(mask) V x_u. Per group (translation,
    // rotation), each block divided by its trace, so that metres and radians never share one
    // eigen-decomposition and the threshold is a share of the group's information.
    const Vec6d d = toVec6(T_ref.inverse() * T_solved);
    Mat6d P_keep = Mat6d::Zero(), P_removed = Mat6d::Zero();
    RemapResult out;
    for (int g = 0; g < 6; g += 3) {
        const Mat3d B = 0.5 * (H.block<3, 3>(g, g) + H.block<3, 3>(g, g).transpose());
        const double trace = B.trace();
        if (!(trace > 0) || !B.allFinite()) {  // nothing constrains the group
            P_removed.block<3, 3>(g, g).setIdentity();
            out.removed += 3;
            continue;
        }
        const Eigen::SelfAdjointEigenSolver<Mat3d> es(B / trace);
        for (int k = 0; k < 3; ++k) {
            const Vec3d v = es.eigenvectors().col(k);
            if (es.eigenvalues()[k] >= threshold) {
                P_keep.block<3, 3>(g, g) += v * v.transpose();
            } else {
                P_removed.block<3, 3>(g, g) += v * v.transpose();
                ++out.removed;
            }
        }
    }
    out.T = T_ref * fromVec6(P_keep * d);
    out.prior_share = P_removed.diagonal();
    return out;
}

}  // namespace superloc::fusion
