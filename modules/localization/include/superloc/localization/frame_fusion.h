// Where odom_alt enters a tracked frame's solve (doc/method.md §2): what the method's fusion
// policy (OdomFusion, method_variant.h) sees of the frame, and the two points of the ICP rounds
// where it acts (RoundFusion): the prior at the risk step, the amendment after each round.
//   OdomAltLink   odom_alt's motion and covariance over the frame (SensorHistory look-ups),
//                 saying once when odom_alt is missing or has a gap
//   FrameFusion   one tracked solve: the scan's information above its noise floor, where the
//                 estimate (scan + IMU window) is weak, then OdomFusion::prior / afterRound
#pragma once

#include <mrpt/system/COutputLogger.h>
#include <superloc/fusion/estimate_information.h>
#include <superloc/localization/method_variant.h>
#include <superloc/localization/registration.h>
#include <superloc/localization/sensor_history.h>

#include <optional>

namespace superloc::localization {

class OdomAltLink {
   public:
    OdomAltLink(const SensorHistory& sensors, const OdomFusion& policy, const fusion::FusionParams& params,
                Method method, const mrpt::system::COutputLogger& log)
        : sensors_(sensors), policy_(policy), params_(params), method_(method), log_(log) {}
    /// What the policy sees of a frame from t_prev to t before its solve: the previous frame's
    /// pose, odom_alt's motion and covariance over the frame (looked up only when the policy
    /// reads odom_alt, and not on a first frame: `have_prev` false).
    FusionFrame frame(bool have_prev, const SE3d& T_map_imu, const SE3d& T_prev_map_imu, double t_prev, double t);
    /// Once a tracked frame is final: the policy's frameDone (odom_alt's calibration) with the
    /// frame's final pose and the evidence of its solve.
    void frameDone(OdomFusion& policy, const FrameSolution& sol, const fusion::FrameState& prev) const;

   private:
    /// odom_alt's motion over the frame, logging when it is missing or a gap starts / ends
    /// (once per episode, not per frame).
    std::optional<SE3d> delta(double t_prev, double t);
    const SensorHistory& sensors_;
    const OdomFusion& policy_;
    const fusion::FusionParams& params_;
    Method method_;
    const mrpt::system::COutputLogger& log_;
    int state_ = 0;  ///< 0 not checked yet, 1 available, -1 missing (logged)
};

class FrameFusion final : public RoundFusion {
   public:
    FrameFusion(const OdomFusion& policy, const fusion::FusionParams& fusion, const risk::RiskParams& risk,
                FusionFrame frame)
        : policy_(policy), fusion_(fusion), risk_(risk), frame_(std::move(frame)) {}
    std::optional<fusion::RelativePosePrior> prior(const std::vector<Correspondence>& corr, const SE3d& T_map_imu,
                                                   const risk::RiskReport& risk, FrameSolution& sol) override;
    RoundAmend afterRound(const SE3d& T_round_start, const fusion::ScanFactor& scan, const SE3d& T_solved) override;

   private:
    const OdomFusion& policy_;
    const fusion::FusionParams& fusion_;
    const risk::RiskParams& risk_;
    FusionFrame frame_;
};

}  // namespace superloc::localization
