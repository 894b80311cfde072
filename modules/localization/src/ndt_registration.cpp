// NdtRegistration: PCL's NDT as a Registration (ndt_registration.h).
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/localization/ndt_registration.h>

namespace superloc::localization {

namespace {
using Clock = SteadyClock;
}  // namespace

NdtRegistration::NdtRegistration(const LocalizerParams& params, const AssociationParams& assoc)
    : fusion_(params.fusion), imu_(params.imu), risk_(params.risk), assoc_(assoc) {}

void NdtRegistration::solve(const RegistrationProblem& p, FrameSolution& sol) const {
    TrackReport& rep = sol.report;
    const SE3d& T_imu_lidar = p.features->T_imu_lidar;
    // The alignment risk is reported for ndt too (not used): correspondences at the start.
    auto ta = Clock::now();
    associate(p.features->pts_body, sol.state.T_map_imu(), *p.map, assoc_, sol.corr, sol.stats);
    rep.ms.associate += msSince(ta);
    ta = Clock::now();
    const auto risk =
        risk::computeAlignmentRisk(sol.corr, sol.state.T_map_imu(), T_imu_lidar.translation(), risk_);
    rep.setRisk(risk);
    rep.ms.risk += msSince(ta);
    const auto t0 = Clock::now();
    const SE3d guess = sol.state.T_map_imu() * T_imu_lidar;
    const AlignResult a = ndt_->align(p.features->ndt_source, guess);
    rep.rounds = 1;
    rep.iterations = a.iterations;
    rep.converged = a.converged;
    const SE3d T_ndt = a.T_target_source * T_imu_lidar.inverse();
    sol.state.setPose(T_ndt);
    if (p.imu) {
        // Loosely coupled, like hdl_localization's filter: the NDT pose as a measurement
        // (sigma scan_sigma, 0.5 deg) with the IMU factor, for velocity and biases.
        Mat6d w = Mat6d::Zero();
        w.diagonal().head<3>().setConstant(1.0 / fusion_.scan_sigma);
        w.diagonal().tail<3>().setConstant(1.0 / (0.5 * kDeg));
        fusion::FrameProblemInputs in;
        in.prev = p.prev;
        in.cur = &sol.state;
        in.setImu(p.imu, imu_);
        in.cur_pose_prior = std::make_pair(T_ndt, w);
        in.prev_prior = p.prev_prior;
        in.marginalize = p.marginalize;
        const auto sum = fusion::solveFrame(in, fusion_);
        sol.marginal = sum.marginal;
        rep.iterations += sum.iterations;
    }
    rep.ms.solve += msSince(t0);
}

}  // namespace superloc::localization
