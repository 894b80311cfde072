// The method variants (doc/localizer.md) as classes with one interface. A method is a registration
// (the Localizer's Ceres point-to-plane/line/point loop, or PCL NDT) and an odom_alt fusion
// policy; the fusion policies are one family, named family + variant as in mp2p_icp:
//
//   method       registration  fusion
//   icp          Icp           OdomFusionNone
//   ndt          Ndt           OdomFusionNone
//   passive      Icp           OdomFusionPassive     relative-pose prior, fixed weight
//   superloc     Icp           OdomFusionActive      odom_alt calibrated online, fused where the
//                                                    estimate (scan + IMU window) is weak
//   superloc_paper Icp         OdomFusionPaper       relative-pose prior weighted by the scan's risk
//                                                    (the paper's W = (1 - gamma) s, ablation)
//   eigen_remap  Icp           OdomFusionEigenRemap  Zhang et al. 2016 solution remapping
//
// The Localizer asks its policy for the prior of each solve (prior()) and lets it amend each
// round's solution (afterRound()); it holds no `if (method == ...)` of its own beyond the
// registration choice.
#pragma once

#include <superloc/core/correspondence.h>
#include <superloc/core/types.h>
#include <superloc/fusion/estimate_information.h>
#include <superloc/fusion/frame_problem.h>
#include <superloc/fusion/fusion_params.h>
#include <superloc/fusion/odom_calibration.h>
#include <superloc/fusion/scan_factor.h>
#include <superloc/localization/frame_report.h>
#include <superloc/localization/localization_params.h>
#include <superloc/risk/alignment_risk.h>

#include <memory>
#include <optional>
#include <vector>

namespace superloc::localization {

enum class RegistrationKind { Icp, Ndt };  ///< which Registration (registration.h) a method tracks with

/// What a fusion policy sees of the frame being solved (body = IMU frame).
struct FusionFrame {
    const std::vector<Correspondence>* corr = nullptr;  ///< the round's correspondences
    SE3d T_map_imu = SE3d::Identity();                  ///< the pose they were associated at
    SE3d T_prev_map_imu = SE3d::Identity();             ///< previous frame's solved pose
    std::optional<SE3d> odom_delta;                     ///< odom_alt body motion over the frame
    std::optional<Mat6d> odom_cov_prev, odom_cov_cur;   ///< odom_alt's covariance at both ends
    /// Where the estimate without odom_alt (scan above its noise floor + IMU window,
    /// fusion::EstimateInformation) is weak before the solve, and where the scan alone is.
    fusion::Weakness est, scan;
    /// The scan's information at the predicted pose from `corr` (fusion::scanInformation, body
    /// axes, before its noise floor): computed once per frame by FrameFusion for every policy.
    Mat6d scan_H = Mat6d::Zero();
    /// The variance of the IMU-carried prediction's body motion over the frame per axis
    /// (EstimateInformation::motionVariance): empty without IMU.
    std::optional<Vec6d> pred_motion_var;
    double dt = 0;  ///< [s] from the previous frame
};

/// What a round's odom_alt fusion kept (OdomFusion::afterRound): the pose, and, when it fused
/// something into it, what it reports as the frame's prior (prior_used, prior_weight).
struct RoundAmend {
    SE3d T = SE3d::Identity();
    bool reports_prior = false;
    bool prior_used = false;
    Vec6d prior_weight = Vec6d::Zero();
};

class OdomFusion {
   public:
    virtual ~OdomFusion() = default;
    /// Whether the policy reads odom_alt (the Localizer then looks it up, and says once when it
    /// is missing).
    virtual bool usesOdomAlt() const { return false; }
    /// The relative-pose prior of this frame's solve, from the risk at the predicted pose.
    virtual std::optional<fusion::RelativePosePrior> prior(const FusionFrame&, const risk::RiskReport&) const {
        return std::nullopt;
    }
    /// After a round's solve: the pose to keep (T_solved unless the policy amends it) and what it
    /// fused into it. `T_round_start`: the round's start pose.
    virtual RoundAmend afterRound(const FusionFrame&, const SE3d& /*T_round_start*/, const fusion::ScanFactor&,
                                  const SE3d& T_solved) const {
        RoundAmend a;
        a.T = T_solved;
        return a;
    }
    /// Without IMU: the body motion over the frame the policy predicts from odom_alt's
    /// (`odom_delta`), used instead of the constant-velocity model; empty: not used.
    virtual std::optional<SE3d> motion(const SE3d& /*odom_delta*/) const { return std::nullopt; }
    /// Once a tracked frame is final (not diverged, lost or relocalized): `f` with T_map_imu
    /// the final pose and odom_alt's motion over the frame (when the policy reads it).
    virtual void frameDone(const FusionFrame& /*f*/) {}
};

/// icp, ndt: the scan alone (and the IMU).
class OdomFusionNone : public OdomFusion {};

/// What odom_alt fused as it is (no correction) is worth, for the pose's covariance of the
/// methods that fuse it so (passive, superloc_paper; doc/method.md §4): its raw motion's error
/// measured out of sample on the axes the scan held (fusion::OdomCalibration without the
/// correction), at the distance since each axis was held. It does not change what the methods
/// fuse, only what their covariance and health say of it.
class RawOdomWorth {
   public:
    explicit RawOdomWorth(const fusion::ActiveFusionParams& p);
    /// Once a frame is final (OdomFusion::frameDone).
    void learn(const FusionFrame& f);
    /// `info` (per-axis information, body axes) capped at what odom_alt's motion `odom_delta`
    /// has shown it is worth (axes not measured yet: `info`).
    Mat6d cap(const Vec6d& info, const SE3d& odom_delta) const;

   private:
    fusion::OdomCalibration raw_;
};

/// passive: the relative-pose prior with a fixed information (doc/method.md §2).
class OdomFusionPassive : public OdomFusion {
   public:
    explicit OdomFusionPassive(const fusion::ActiveFusionParams& p) : p_(p), worth_(p) {}
    bool usesOdomAlt() const override { return true; }
    std::optional<fusion::RelativePosePrior> prior(const FusionFrame& f, const risk::RiskReport&) const override;
    void frameDone(const FusionFrame& f) override { worth_.learn(f); }

   private:
    fusion::ActiveFusionParams p_;
    RawOdomWorth worth_;
};

/// superloc (doc/method.md §2): odom_alt's motion, its systematic error fitted online on the
/// axes the scan holds (fusion::OdomCalibration) and removed, fused in proportion to how weak
/// the estimate without it is along each direction, with the information it is worth there:
///   W = G diag(1 / sigma_odom,k^2) G,   G = FusionFrame::est.G (fusion::weakness)
/// sigma_odom: what the calibration has shown out of sample at the distance since the scan last
/// held the axis (fusion::OdomCalibration::sigma), else the growth of odom_alt's reported std
/// over the frame, else the passive prior's sigmas. An innovation test against the IMU-carried
/// prediction (chi-square, 1 dof per weak axis, 99 %) widens sigma_odom on an axis where the
/// two disagree beyond what both claim, to the variance that explains the disagreement.
class OdomFusionActive : public OdomFusion {
   public:
    OdomFusionActive(const fusion::ActiveFusionParams& p, const Vec6d& weak_sigma);
    bool usesOdomAlt() const override { return true; }
    std::optional<fusion::RelativePosePrior> prior(const FusionFrame& f, const risk::RiskReport& risk) const override;
    void frameDone(const FusionFrame& f) override;
    /// odom_alt's motion, calibrated (the prediction without IMU).
    std::optional<SE3d> motion(const SE3d& odom_delta) const override;
    const fusion::OdomCalibration& calibration() const { return calib_; }

   private:
    fusion::ActiveFusionParams p_;
    Vec6d weak_;
    fusion::OdomCalibration calib_;
};

/// superloc_paper: the relative-pose prior on the axes the scan's risk flags,
/// W = diag(max(0, 1 - gamma)) s (paper §III-C; doc/method.md §2, the ablation).
class OdomFusionPaper : public OdomFusion {
   public:
    explicit OdomFusionPaper(const fusion::ActiveFusionParams& p) : p_(p), worth_(p) {}
    bool usesOdomAlt() const override { return true; }
    std::optional<fusion::RelativePosePrior> prior(const FusionFrame& f, const risk::RiskReport& risk) const override;
    void frameDone(const FusionFrame& f) override { worth_.learn(f); }

   private:
    fusion::ActiveFusionParams p_;
    RawOdomWorth worth_;
};

/// eigen_remap (Zhang, Kaess, Singh, ICRA 2016): each round's update is kept along the
/// eigen-directions of the scan Hessian's translation and rotation blocks whose share of the
/// block's information is at least `eigen_threshold`; along the others the pose stays at the
/// motion prior, as in Zhang et al.: the previous pose × odom_alt's motion over the frame, else
/// the round's start pose (doc/method.md §2).
class OdomFusionEigenRemap : public OdomFusion {
   public:
    explicit OdomFusionEigenRemap(const fusion::ActiveFusionParams& p) : p_(p) {}
    bool usesOdomAlt() const override { return true; }
    RoundAmend afterRound(const FusionFrame& f, const SE3d& T_round_start, const fusion::ScanFactor& scan,
                          const SE3d& T_solved) const override;

   private:
    fusion::ActiveFusionParams p_;
};

struct MethodVariant {
    RegistrationKind registration = RegistrationKind::Icp;
    std::unique_ptr<OdomFusion> fusion;
};

/// The variant of a method (table above).
MethodVariant makeMethodVariant(Method m, const fusion::FusionParams& params, const risk::RiskParams& risk);

}  // namespace superloc::localization
