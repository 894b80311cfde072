// IcpRegistration: coarse-to-fine association and joint solve (icp_registration.h).
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/localization/icp_registration.h>

#include <algorithm>
#include <cmath>

namespace superloc::localization {

namespace {
using Clock = SteadyClock;
}  // namespace

IcpRegistration::IcpRegistration(const LocalizerParams& params)
    : lp_(params.loc),
      fusion_(params.fusion),
      imu_(params.imu),
      risk_(params.risk),
      assoc_(trackingAssociation(params.loc, params.features)),
      kernel_(fusion::robustKernelFromString(params.fusion.robust_kernel)) {}

void IcpRegistration::solve(const RegistrationProblem& p, FrameSolution& sol, FrameReport& rep) const {
    const map::PriorMap& map = *p.map;
    const std::vector<Vec3d>& pts_body = p.features->pts_body;
    const bool from_hypothesis = p.purpose == SolvePurpose::Hypothesis;
    const bool fused = p.purpose == SolvePurpose::Track;  // odom_alt prior, IMU window
    // The window's previous state as the solve found it: each round starts from it again.
    fusion::FrameState no_prev;
    fusion::FrameState& prev = p.prev ? *p.prev : no_prev;
    const fusion::FrameState prev_saved = prev;
    const int rounds = p.wide ? lp_.rounds_init : lp_.rounds;
    // Each correspondence carries its point's time in the sweep (the sweep's share of the pose's
    // covariance, Tracker::sweepCovariance).
    std::vector<uint32_t> feature_of;
    const std::vector<float>& rel_time = p.features->rel_time;
    const bool timed = rel_time.size() == pts_body.size();
    const auto associateAt = [&](const SE3d& T, const AssociationParams& ap) {
        associate(pts_body, T, map, ap, sol.corr, sol.stats, timed ? &feature_of : nullptr);
        if (timed)
            for (size_t j = 0; j < sol.corr.size(); ++j) sol.corr[j].rel_time = rel_time[feature_of[j]];
    };
    // Coarse to fine. association = voxel (doc/map.md): over the voxel map's levels; a frame
    // whose prediction may be far off (velocity unknown: first frame, no velocity yet, a gap)
    // starts at the coarsest level, whose metre-sized voxels give a wide basin, a tracked frame
    // at the finest. Within a level the robust kernel's scale halves every round from a quarter
    // of the voxel edge (half on wide frames) down to the level's floor (kernel_scale at the
    // finest, doubled per level); once the pose settles at the floor, the next finer level takes
    // over; at the finest, it has converged. The gate is max_corr_dist, doubled per level.
    // association = nearest: the search radius starts at max_corr_dist_init on wide frames and
    // shrinks by 0.7 each time the pose settles, down to max_corr_dist; the kernel halves from
    // radius/2 to kernel_scale within each radius.
    // A hypothesis of the global search is solved in the voxel map whatever the tracking
    // association (its metre-sized levels forgive the search's 0.25 m / 1.5 deg steps), without
    // the odom_alt prior or eigen_remap (both hold the pose to the previous frame's, which is
    // exactly what is in question).
    const bool voxel = assoc_.voxel || from_hypothesis;
    const int n_levels = voxel ? map.voxels().levels() : 1;
    // A hypothesis starts one level below the coarsest at most (1 m by default): the search's
    // refinement has brought it within a few decimetres, and the 2 m level's plane biases in
    // small rooms pushed right hypotheses away (simulated office: the right pose then lost to a
    // look-alike room).
    int level = voxel && p.wide ? (from_hypothesis ? std::min(1, n_levels - 1) : n_levels - 1) : 0;
    double radius = !voxel && p.wide ? lp_.max_corr_dist_init : lp_.max_corr_dist;
    int in_stage = 0;
    sol.stats = {};
    sol.corr.clear();
    std::optional<fusion::RelativePosePrior> prior;
    for (int r = 0; r < rounds; ++r, ++in_stage) {
        // Step 3: associate at the current estimate (the prediction on round 0).
        const double scale = voxel ? std::pow(2.0, level) : 1.0;
        AssociationParams ap = assoc_;
        ap.voxel = voxel;
        ap.level = level;
        ap.max_dist = voxel ? lp_.max_corr_dist * scale : radius;
        const double floor = fusion_.kernel_scale * scale;
        const double kernel =
            std::max(floor, voxel ? (p.wide ? 0.5 : 0.25) * map.voxels().levelSize(level) * std::pow(0.5, in_stage)
                                  : 0.5 * radius * std::pow(0.5, in_stage));
        const bool finest = voxel ? level == 0 : radius <= lp_.max_corr_dist;
        const SE3d T_before = sol.state.T_map_imu();
        auto t0 = Clock::now();
        associateAt(T_before, ap);
        rep.ms.associate += msSince(t0);
        if (r == 0 || (voxel && level == 0 && in_stage == 0 && p.wide)) {
            // Step 4: alignment risk before the optimisation at this resolution (doc/method.md): at
            // the predicted pose, and for a wide frame again when the finest level starts.
            t0 = Clock::now();
            const auto risk =
                risk::computeAlignmentRisk(sol.corr, T_before, p.features->T_imu_lidar.translation(), risk_);
            rep.setRisk(risk);
            if (fused) prior = p.fusion->prior(sol.corr, T_before, risk, sol, rep);
            rep.ms.risk += msSince(t0);
        }
        if (sol.corr.size() < kMinCorrespondences && !p.imu) {
            if (voxel && level > 0) {  // nothing at this level: try the next finer one
                --level;
                in_stage = -1;
                continue;
            }
            rep.diverged = true;
            rep.diverged_reason = Divergence::NoCorrespondences;
            break;
        }
        // Step 5: joint solve (paper eq. 12) with IRLS weights at the association pose.
        t0 = Clock::now();
        // The factor borrows the round's correspondences and gives them back at the end of the
        // round (no 2000-element copy per round; sol.corr keeps its capacity).
        fusion::ScanFactor scan(std::move(sol.corr), fusion_.scan_sigma * scale);
        struct GiveBack {
            fusion::ScanFactor& f;
            std::vector<Correspondence>& v;
            ~GiveBack() { v = f.release(); }
        } give_back{scan, sol.corr};
        scan.setRobustWeights(T_before, kernel_, kernel);
        prev = prev_saved;
        fusion::FrameProblemInputs in;
        in.prev = &prev;
        in.cur = &sol.state;
        in.scan = scan.correspondences().size() >= kMinCorrespondences ? &scan : nullptr;
        in.setImu(p.imu, imu_);
        in.prior = prior;
        in.prev_prior = fused ? p.prev_prior : nullptr;
        // Only the last round's marginal is kept: ask for it on a round that can be the last
        // (finest resolution with the kernel at its floor, or the last allowed round).
        in.marginalize = p.marginalize && fused && ((finest && kernel <= floor) || r == rounds - 1);
        const auto sum = fusion::solveFrame(in, fusion_);
        if (fused) sol.marginal = sum.marginal;
        rep.ms.solve += msSince(t0);
        rep.rounds = r + 1;
        rep.iterations += sum.iterations;
        rep.prior_used = prior.has_value();
        rep.final_level = level;
        if (!sum.usable) {
            rep.diverged = true;
            rep.diverged_reason = Divergence::Solver;
            break;
        }
        if (fused) {  // the method's odom_alt fusion may amend the round's solution
            const SE3d T_solved = sol.state.T_map_imu();
            const SE3d T_kept = p.fusion->afterRound(T_before, scan, T_solved, rep);
            if (T_kept.matrix() != T_solved.matrix()) sol.state.setPose(T_kept);
        }
        const SE3d T_after = sol.state.T_map_imu();
        rep.last_step_xyz = translationDistance(T_before, T_after);
        rep.last_step_deg = rotationAngle(T_before, T_after) / kDeg;
        const bool small = translationDistance(T_before, T_after) < lp_.converged_xyz * scale &&
                           rotationAngle(T_before, T_after) < lp_.converged_deg * scale * kDeg;
        if (small && kernel <= floor) {
            if (finest) {
                rep.converged = true;
                break;
            }
            if (voxel)
                --level;
            else
                radius = std::max(lp_.max_corr_dist, 0.7 * radius);
            in_stage = -1;
        }
    }
    if (voxel && level > 0 && !rep.diverged) {
        // The rounds ran out before the finest level: associate there once more so that the
        // frame's quality is measured at full resolution.
        AssociationParams ap = assoc_;
        ap.voxel = voxel;
        const auto t0 = Clock::now();
        associateAt(sol.state.T_map_imu(), ap);
        rep.ms.associate += msSince(t0);
    }
    if (prior) rep.prior_weight = (prior->sqrt_info.transpose() * prior->sqrt_info).diagonal();
    if (fused) sol.prior = prior;
}

}  // namespace superloc::localization
