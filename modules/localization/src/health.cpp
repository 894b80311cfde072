#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/fusion/pose_posterior.h>
#include <superloc/localization/frame_report.h>
#include <superloc/localization/health.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace superloc::localization {

const char* divergenceName(Divergence d) {
    switch (d) {
        case Divergence::None: return "";
        case Divergence::Inliers: return "inliers";
        case Divergence::Jump: return "jump";
        case Divergence::JumpRejected: return "jump_rejected";
        case Divergence::NoCorrespondences: return "no_correspondences";
        case Divergence::Solver: return "solver";
        case Divergence::NoPose: return "no_pose";
    }
    return "?";
}

const char* healthName(Health h) {
    switch (h) {
        case Health::Ok: return "ok";
        case Health::Degraded: return "degraded";
        case Health::Lost: return "lost";
    }
    return "?";
}

void HealthParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(weak_gamma, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_sigma_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_sigma_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_dead_reckoning_s, double, c, s);
    MRPT_LOAD_CONFIG_VAR(degraded_inlier_drop, double, c, s);
    MRPT_LOAD_CONFIG_VAR(lost_inlier_drop, double, c, s);
    MRPT_LOAD_CONFIG_VAR(reference_frames, int, c, s);
    MRPT_LOAD_CONFIG_VAR(reference_min_frames, int, c, s);
    MRPT_LOAD_CONFIG_VAR(settled_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(settled_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_pred_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_pred_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(drift_window, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_drift_deg, double, c, s);
}

void HealthParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(weak_gamma, "[-] an axis with gamma below: weak (weak_axes; not degraded by itself)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_sigma_xyz, "[m] the pose's position std above: degraded");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_sigma_deg, "[deg] the pose's rotation std above: degraded");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_dead_reckoning_s, "[s] a weak axis held by neither the scan nor odom_alt longer: degraded");
    MRPT_SAVE_CONFIG_VAR_COMMENT(degraded_inlier_drop, "[-] inlier ratio below this x the reference: degraded");
    MRPT_SAVE_CONFIG_VAR_COMMENT(lost_inlier_drop, "[-] inlier ratio below this x the reference: lost");
    MRPT_SAVE_CONFIG_VAR_COMMENT(reference_frames, "tracked frames in the reference inlier ratio (median)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(reference_min_frames, "the relative inlier checks start with this many");
    MRPT_SAVE_CONFIG_VAR_COMMENT(settled_xyz, "[m] out of rounds with a last update above: not converged");
    MRPT_SAVE_CONFIG_VAR_COMMENT(settled_deg, "[deg] ...or a last rotation update above");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_pred_xyz, "[m] IMU prediction vs solved position farther: degraded");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_pred_deg, "[deg] IMU prediction vs solved rotation farther: degraded");
    MRPT_SAVE_CONFIG_VAR_COMMENT(drift_window, "[s] window of the gyro drift check (0 = off)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_drift_deg, "[deg] solved vs gyro-carried rotation over the window farther: degraded");
}

void HealthParams::validate() const {
    const auto in01 = [](double v, const char* key) {
        if (!(v >= 0 && v <= 1)) throw ConfigError(std::string("[health] ") + key + " must be in [0, 1]");
    };
    in01(weak_gamma, "weak_gamma");
    if (!(max_sigma_xyz > 0) || !(max_sigma_deg > 0))
        throw ConfigError("[health] max_sigma_xyz and max_sigma_deg must be > 0");
    if (!(max_dead_reckoning_s >= 0)) throw ConfigError("[health] max_dead_reckoning_s must be >= 0");
    in01(degraded_inlier_drop, "degraded_inlier_drop");
    in01(lost_inlier_drop, "lost_inlier_drop");
    if (lost_inlier_drop > degraded_inlier_drop)
        throw ConfigError("[health] lost_inlier_drop must not exceed degraded_inlier_drop");
    if (reference_frames < 1) throw ConfigError("[health] reference_frames must be >= 1");
    if (reference_min_frames < 1 || reference_min_frames > reference_frames)
        throw ConfigError("[health] reference_min_frames must be in [1, reference_frames]");
    if (!(settled_xyz > 0) || !(settled_deg > 0))
        throw ConfigError("[health] settled_xyz and settled_deg must be > 0");
    if (!(max_pred_xyz > 0)) throw ConfigError("[health] max_pred_xyz must be > 0");
    if (!(max_pred_deg > 0)) throw ConfigError("[health] max_pred_deg must be > 0");
    if (!(drift_window >= 0 && drift_window <= 10)) throw ConfigError("[health] drift_window must be in [0, 10] s");
    if (!(max_drift_deg > 0)) throw ConfigError("[health] max_drift_deg must be > 0");
}

bool HealthJudge::notConverged(const FrameReport& r) const {
    return !r.converged &&
           (r.final_level > 0 || r.last_step_xyz > p_->settled_xyz || r.last_step_deg > p_->settled_deg);
}

double HealthMonitor::reference() const {
    if (tracked_.size() < static_cast<size_t>(p_.reference_min_frames)) return 0;
    std::vector<double> v(tracked_.begin(), tracked_.end());
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

HealthChecks HealthJudge::check(const FrameReport& r) const {
    const HealthParams& p = *p_;
    const double ref = reference_;
    HealthChecks c;
    // As health_reason says: a diverged frame is lost for that alone, a frame lost by its
    // inliers for those alone; only a frame that stands has its other checks made.
    c.diverged = r.diverged && r.diverged_reason != Divergence::JumpRejected;
    if (c.diverged) return c;
    c.inliers_lost = ref > 0 && r.inlier_ratio < p.lost_inlier_drop * ref;
    if (c.inliers_lost) return c;
    c.jump_rejected = r.diverged;  // the IMU prediction was kept
    c.inliers = ref > 0 && r.inlier_ratio < p.degraded_inlier_drop * ref;
    c.not_converged = notConverged(r);
    for (int k = 0; k < 6; ++k) c.weak[k] = r.gamma[k] < p.weak_gamma;
    // The pose's std: the largest over directions (the covariance's largest eigenvalue per
    // group); a frame without a covariance (zero) passes.
    c.sigma_xyz = fusion::largestStd(r.cov.topLeftCorner<3, 3>()) > p.max_sigma_xyz;
    c.sigma_rot = fusion::largestStd(r.cov.bottomRightCorner<3, 3>()) > p.max_sigma_deg * kDeg;
    c.dead_reckoning = r.dead_reckoning_s > p.max_dead_reckoning_s;
    c.prediction = r.used_imu && (r.pred_dxyz > p.max_pred_xyz || r.pred_ddeg > p.max_pred_deg);
    c.drift = r.used_imu && p.drift_window > 0 && r.imu_drift_deg > p.max_drift_deg;
    return c;
}

Verdict HealthJudge::operator()(const FrameReport& r) const {
    Verdict v;
    v.inlier_reference = reference_;
    v.checks = check(r);
    const HealthChecks& c = v.checks;
    std::string& why = v.reason;
    const auto add = [&why](const std::string& s) { why += (why.empty() ? "" : "+") + s; };
    Health& h = v.health;
    h = Health::Ok;
    if (c.diverged) {
        add(r.diverged_reason == Divergence::None ? "diverged" : divergenceName(r.diverged_reason));
        h = Health::Lost;
    } else if (c.inliers_lost) {
        add("inliers");
        h = Health::Lost;
    } else {
        if (c.jump_rejected) add(divergenceName(r.diverged_reason));
        if (c.not_converged) add("not_converged");
        if (c.sigma_xyz) add("sigma_xyz");
        if (c.sigma_rot) add("sigma_rot");
        if (c.dead_reckoning) add("dead_reckoning");
        if (c.inliers) add("inliers");
        if (c.prediction) add("prediction");
        if (c.drift) add("drift");
        if (!why.empty()) h = Health::Degraded;
    }
    return v;
}

Verdict HealthJudge::amend(Verdict v, HealthEvidence e) const {
    switch (e) {
        case HealthEvidence::Unconfirmed:
            if (v.health != Health::Ok) break;
            v.health = Health::Degraded;
            v.reason = "unconfirmed";
            v.checks.unconfirmed = true;
            break;
        case HealthEvidence::Confirmed:
            if (!v.checks.unconfirmed) break;
            v.health = Health::Ok;
            v.reason.clear();
            v.checks.unconfirmed = false;
            break;
        case HealthEvidence::StartAmbiguous:
            if (v.health != Health::Ok) break;
            v.health = Health::Degraded;
            v.reason = "start_ambiguous";
            break;
    }
    return v;
}

double HealthMonitor::imuDrift(const FrameReport& rep) const {
    const double window = p_.drift_window;
    if (!rep.used_imu || window <= 0 || drift_chain_.empty()) return 0.0;
    // R_j = R_k * dR_{k+1} * ... * dR_j along the chain; M accumulates the dR from k on.
    Eigen::Matrix3d M = drift_chain_.back().R.transpose() * rep.T_map_lidar_pred.linear();  // dR_j
    const Eigen::Matrix3d& Rj = rep.T_map_lidar.linear();
    double drift = 0;
    bool spanned = false;
    for (size_t k = drift_chain_.size(); k-- > 0;) {
        const DriftSample& s = drift_chain_[k];
        if (rep.t - s.t > window + 1e-6) break;
        if (rep.t - s.t >= 0.5 * window) {
            drift = Eigen::AngleAxisd((s.R * M).transpose() * Rj).angle() * 180.0 / M_PI;
            spanned = true;
        }
        M = s.dR_pred * M;
    }
    return spanned ? drift : 0.0;
}

void HealthMonitor::commit(const FrameReport& rep, bool chained) {
    // The reference: a frame whose fit itself is sound (weak axes aside, which say nothing about
    // this map's inlier ratio when tracking is right), once.
    const HealthChecks& c = rep.checks;
    if (!rep.diverged && !c.not_converged && !c.badFit() && !c.prediction && !c.drift) {
        tracked_.push_back(rep.inlier_ratio);
        while (tracked_.size() > static_cast<size_t>(p_.reference_frames)) tracked_.pop_front();
    }
    const bool stands = rep.health != Health::Lost && !rep.diverged;
    if (!chained || !stands || drift_chain_.empty()) drift_chain_.clear();
    if (!stands) return;
    DriftSample s;
    s.t = rep.t;
    s.R = rep.T_map_lidar.linear();
    if (!drift_chain_.empty()) s.dR_pred = drift_chain_.back().R.transpose() * rep.T_map_lidar_pred.linear();
    drift_chain_.push_back(s);
    while (drift_chain_.size() > 2 && rep.t - drift_chain_[1].t > p_.drift_window) drift_chain_.pop_front();
}

}  // namespace superloc::localization
