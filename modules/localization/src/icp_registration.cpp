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
      assoc_(trackingAssociation(params.assoc, params.loc, params.features)),
      kernel_(fusion::robustKernelFromString(params.fusion.robust_kernel)) {}

// Coarse to fine. association = voxel (doc/map.md): over the voxel map's levels; a frame whose
// prediction may be far off (velocity unknown: first frame, no velocity yet, a gap) starts at the
// coarsest level, whose metre-sized voxels give a wide basin, a tracked frame at the finest.
// Within a level the robust kernel's scale halves every round from a quarter of the voxel edge
// (half on wide frames) down to the level's floor (kernel_scale at the finest, doubled per
// level); once the pose settles at the floor, the next finer level takes over; at the finest, it
// has converged. The gate is max_corr_dist, doubled per level.
// association = nearest: the search radius starts at max_corr_dist_init on wide frames and
// shrinks by 0.7 each time the pose settles, down to max_corr_dist; the kernel halves from
// radius/2 to kernel_scale within each radius.
// association = planes: as nearest; the rounds whose radius is still above max_corr_dist (a wide
// frame's first ones) search the kd-tree as nearest does, the others the bounded planes
// association. The last scan's registration (LastScan) is nearest's throughout.
// A hypothesis of the global search is solved in the voxel map whatever the tracking
// association (its metre-sized levels forgive the search's 0.25 m / 1.5 deg steps), and starts
// one level below the coarsest at most (1 m by default): the search's refinement has brought it
// within a few decimetres, and the 2 m level's plane biases in small rooms pushed right
// hypotheses away (simulated office: the right pose then lost to a look-alike room).
class IcpRegistration::Schedule {
   public:
    Schedule(const LocalizationParams& lp, const AssociationParams& base, double kernel_scale,
             const map::VoxelMap& voxels, bool voxel, bool wide, bool hypothesis, bool may_settle,
             bool one_anneal = false)
        : lp_(lp),
          base_(base),
          kernel_scale_(kernel_scale),
          voxels_(voxels),
          voxel_(voxel),
          wide_(wide),
          level_(voxel && wide ? (hypothesis ? std::min(1, voxels.levels() - 1) : voxels.levels() - 1) : 0),
          radius_(!voxel && wide ? lp.max_corr_dist_init : lp.max_corr_dist),
          radius0_(radius_),
          may_settle_(may_settle),
          one_anneal_(one_anneal && !voxel) {}

    bool voxel() const { return voxel_; }
    int level() const { return level_; }
    double scale() const { return voxel_ ? std::pow(2.0, level_) : 1.0; }
    /// The round's association: the base at this level (voxel) or radius (nearest, planes).
    AssociationParams association() const {
        AssociationParams base = base_;
        if (voxel_)
            base.kind = AssociationKind::Voxel;
        else if (base.kind == AssociationKind::Voxel || (base.kind == AssociationKind::Planes && radius_ > lp_.max_corr_dist))
            base.kind = AssociationKind::Nearest;
        base.level = level_;
        base.max_dist = voxel_ ? lp_.max_corr_dist * scale() : radius_;
        return base;
    }
    double kernelFloor() const { return kernel_scale_ * scale(); }
    double kernel() const {
        if (settled_) return kernelFloor();
        if (one_anneal_) return std::max(kernelFloor(), 0.5 * radius0_ * std::pow(0.5, in_stage_));
        return std::max(kernelFloor(), voxel_ ? (wide_ ? 0.5 : 0.25) * voxels_.levelSize(level_) * std::pow(0.5, in_stage_)
                                              : 0.5 * radius_ * std::pow(0.5, in_stage_));
    }
    bool finest() const { return voxel_ ? level_ == 0 : radius_ <= lp_.max_corr_dist; }
    /// A round that may be the last: finest resolution with the kernel at its floor.
    bool atFloor() const { return finest() && kernel() <= kernelFloor(); }
    /// The alignment risk is measured on the first round, and on a wide frame's first round at
    /// the finest level (doc/method.md).
    bool measuresRisk(int round) const { return round == 0 || (voxel_ && level_ == 0 && in_stage_ == 0 && wide_); }
    /// Nothing to register at this level: the next finer one (false: none is left).
    bool finer() {
        if (!(voxel_ && level_ > 0)) return false;
        --level_;
        in_stage_ = -1;
        return true;
    }
    /// After a round that moved the pose by (dxyz [m], drot [rad]): whether the solve has
    /// converged; a pose settled at the kernel's floor above the finest resolution moves on to
    /// the next finer one.
    bool converged(double dxyz, double drot) {
        const bool small = dxyz < lp_.converged_xyz * scale() && drot < lp_.converged_deg * scale() * kDeg;
        if (!(small && kernel() <= kernelFloor())) {
            // A tracked frame whose round moved the pose less than settle_xyz / settle_deg at the
            // finest resolution was predicted within the kernel floor's scale: the rounds left
            // run at the floor (no annealing left to do), and it stops once settled there. Only
            // where the last frame confirmed the motion prediction (RegistrationProblem::
            // may_settle): not after a wide, ambiguous or last-scan start, never a search's
            // hypothesis.
            if (may_settle_ && finest() && dxyz < lp_.settle_xyz && drot < lp_.settle_deg * kDeg) settled_ = true;
            return false;
        }
        if (finest()) return true;
        if (voxel_)
            --level_;
        else
            radius_ = std::max(lp_.max_corr_dist, 0.7 * radius_);
        in_stage_ = -1;
        return false;
    }
    void next() {
        ++in_stage_;
        // One annealing: the radius follows the kernel down (six kernel scales) instead of
        // annealing the kernel again at each radius.
        if (one_anneal_) radius_ = std::max(lp_.max_corr_dist, std::min(radius_, 6.0 * kernel()));
    }

   private:
    const LocalizationParams& lp_;
    AssociationParams base_;
    double kernel_scale_;
    const map::VoxelMap& voxels_;
    bool voxel_, wide_;
    int level_;
    double radius_;
    double radius0_;  ///< the first round's radius
    int in_stage_ = 0;
    bool may_settle_;       ///< a tracked frame's solve whose prediction the last frame confirmed
    bool one_anneal_;       ///< nearest: one annealing of kernel and radius together (LastScan)
    bool settled_ = false;  ///< the kernel at its floor from the next round on
};

AssociationMemo& IcpRegistration::freshMemo() {
    thread_local AssociationMemo memo;
    memo.clear();
    return memo;
}

void IcpRegistration::associateAt(const RegistrationProblem& p, const SE3d& T, const AssociationParams& ap,
                                  Scratch& scratch, FrameSolution& sol) const {
    // Each correspondence carries its point's time in the sweep (the sweep's share of the pose's
    // covariance, Tracker::sweepCovariance).
    const std::vector<float>& rel_time = p.features->rel_time;
    const bool timed = rel_time.size() == p.features->pts_body.size();
    const auto t0 = Clock::now();
    std::vector<uint32_t>& feature_of = scratch.feature_of;
    AssociationParams a = ap;
    if (scratch.point_geometry) a.voxel_planes = false;
    associate(p.features->pts_body, T, *p.map, a, sol.corr, sol.stats, timed ? &feature_of : nullptr,
              &scratch.nearest_hint, &scratch.memo);
    if (timed)
        for (size_t j = 0; j < sol.corr.size(); ++j) sol.corr[j].rel_time = rel_time[feature_of[j]];
    sol.report.ms.associate += msSince(t0);
}

IcpRegistration::Round IcpRegistration::round(const RegistrationProblem& p, const Schedule& s, int r, int rounds,
                                              const fusion::FrameState& prev_saved,
                                              std::optional<fusion::RelativePosePrior>& prior,
                                              Scratch& scratch, FrameSolution& sol) const {
    TrackReport& rep = sol.report;
    const bool fused = p.purpose == SolvePurpose::Track;  // odom_alt prior, IMU window
    const double kernel = s.kernel();
    const SE3d T_before = sol.state.T_map_imu();
    const AssociationParams ap = s.association();
    // Step 3: associate at the current estimate (the prediction on round 0).
    associateAt(p, T_before, ap, scratch, sol);
    if (s.measuresRisk(r)) {
        // Step 4: alignment risk before the optimisation at this resolution (doc/method.md).
        const auto assessRisk = [&] {
            const auto t0 = Clock::now();
            auto risk = risk::computeAlignmentRisk(sol.corr, T_before, p.features->T_imu_lidar.translation(), risk_);
            rep.ms.risk += msSince(t0);
            return risk;
        };
        auto risk = assessRisk();
        if (ap.kind == AssociationKind::Planes && !scratch.point_geometry && ap.plane.wantsPointGeometry(risk.gamma)) {
            // Weak in translation (a corridor's axis; [association] points_below_gamma): what
            // holds that axis is a surface's texture, which a voxel plane smooths away (its
            // centroid and mean normal); each map point's own geometry keeps it, as `nearest`
            // does. The frame is associated and its risk measured again that way, and keeps it
            // for its later rounds (doc/map.md).
            scratch.point_geometry = true;
            associateAt(p, T_before, ap, scratch, sol);
            risk = assessRisk();
        }
        const auto t0 = Clock::now();
        rep.setRisk(risk);
        if (fused) prior = p.fusion->prior(sol.corr, T_before, risk, sol);
        rep.ms.risk += msSince(t0);
    }
    Round out;
    if (sol.corr.size() < kMinCorrespondences && !p.imu) {
        out.end = Round::End::Sparse;
        return out;
    }
    // Step 5: joint solve (paper eq. 12) with IRLS weights at the association pose.
    const auto t0 = Clock::now();
    // The factor borrows the round's correspondences and gives them back at the end of the
    // round (no 2000-element copy per round; sol.corr keeps its capacity).
    fusion::ScanFactor scan(std::move(sol.corr), fusion_.scan_sigma * s.scale());
    struct GiveBack {
        fusion::ScanFactor& f;
        std::vector<Correspondence>& v;
        ~GiveBack() { v = f.release(); }
    } give_back{scan, sol.corr};
    scan.setRobustWeights(T_before, kernel_, kernel);
    // The window's previous state as the solve found it: each round starts from it again.
    fusion::FrameState no_prev;
    fusion::FrameState& prev = p.prev ? *p.prev : no_prev;
    prev = prev_saved;
    fusion::FrameProblemInputs in;
    in.prev = &prev;
    in.cur = &sol.state;
    in.scan = scan.correspondences().size() >= kMinCorrespondences ? &scan : nullptr;
    in.setImu(p.imu, imu_);
    in.prior = prior;
    in.prev_prior = fused ? p.prev_prior : nullptr;
    // Only the last round's marginal is kept: ask for it on a round that can be the last.
    in.marginalize = p.marginalize && fused && (s.atFloor() || r == rounds - 1);
    const auto sum = fusion::solveFrame(in, fusion_);
    if (fused) sol.marginal = sum.marginal;
    rep.ms.solve += msSince(t0);
    rep.rounds = r + 1;
    rep.iterations += sum.iterations;
    rep.prior_used = prior.has_value();
    rep.final_level = s.level();
    if (!sum.usable) {
        out.end = Round::End::Unusable;
        return out;
    }
    if (fused) {  // the method's odom_alt fusion may amend the round's solution
        const SE3d T_solved = sol.state.T_map_imu();
        const RoundAmend kept = p.fusion->afterRound(T_before, scan, T_solved);
        if (kept.reports_prior) rep.prior_used = kept.prior_used, rep.prior_weight = kept.prior_weight;
        if (kept.T.matrix() != T_solved.matrix()) sol.state.setPose(kept.T);
    }
    const SE3d T_after = sol.state.T_map_imu();
    out.step_xyz = translationDistance(T_before, T_after);
    out.step_rad = rotationAngle(T_before, T_after);
    rep.last_step_xyz = out.step_xyz;
    rep.last_step_deg = out.step_rad / kDeg;
    return out;
}

void IcpRegistration::solve(const RegistrationProblem& p, FrameSolution& sol) const {
    TrackReport& rep = sol.report;
    const map::PriorMap& map = *p.map;
    const bool hypothesis = p.purpose == SolvePurpose::Hypothesis;
    AssociationParams base = assoc_;
    if (p.purpose == SolvePurpose::LastScan && base.kind == AssociationKind::Planes) base.kind = AssociationKind::Nearest;
    Schedule sched(lp_, base, fusion_.kernel_scale, map.voxels(), base.voxel() || hypothesis, p.wide, hypothesis,
                   p.may_settle, p.purpose == SolvePurpose::LastScan);
    const int rounds = p.wide ? lp_.rounds_init : lp_.rounds;
    const fusion::FrameState prev_saved = p.prev ? *p.prev : fusion::FrameState{};
    Scratch scratch;
    // The last frame was weak in translation: no voxel planes from the first round (one
    // association saved; the risk is then measured on the points' own geometry).
    scratch.point_geometry = p.without_voxel_planes && base.kind == AssociationKind::Planes;
    std::optional<fusion::RelativePosePrior> prior;
    sol.stats = {};
    sol.corr.clear();
    for (int r = 0; r < rounds; ++r, sched.next()) {
        const Round o = round(p, sched, r, rounds, prev_saved, prior, scratch, sol);
        if (o.end == Round::End::Sparse) {
            if (sched.finer()) continue;  // nothing at this level: try the next finer one
            rep.diverged = true;
            rep.diverged_reason = Divergence::NoCorrespondences;
            break;
        }
        if (o.end == Round::End::Unusable) {
            rep.diverged = true;
            rep.diverged_reason = Divergence::Solver;
            break;
        }
        if (sched.converged(o.step_xyz, o.step_rad)) {
            rep.converged = true;
            break;
        }
    }
    if (sched.voxel() && sched.level() > 0 && !rep.diverged) {
        // The rounds ran out before the finest level: associate there once more so that the
        // frame's quality is measured at full resolution.
        AssociationParams ap = assoc_;
        ap.kind = AssociationKind::Voxel;
        associateAt(p, sol.state.T_map_imu(), ap, scratch, sol);
    }
    if (prior) rep.prior_weight = (prior->sqrt_info.transpose() * prior->sqrt_info).diagonal();
    if (p.purpose == SolvePurpose::Track) sol.prior = prior;
}

}  // namespace superloc::localization
