// The Tracker: one frame from its prediction to its solution (tracker.h).
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/localization/tracker.h>

#include <cmath>

namespace superloc::localization {

namespace {
using Clock = SteadyClock;
}  // namespace

Tracker::Tracker(const LocalizerParams& params, const MethodVariant& variant, const SensorHistory& sensors,
                 const mrpt::system::COutputLogger& log)
    : params_(params),
      variant_(variant),
      sensors_(sensors),
      log_(log),
      g_map_(0, 0, -params.imu.gravity),
      preproc_(params.features),
      icp_(params),
      ndt_(params, icp_.association()),
      reg_(variant.registration == RegistrationKind::Ndt ? static_cast<const Registration*>(&ndt_) : &icp_),
      odom_link_(sensors, *variant.fusion, params_.fusion, params.loc.method, log),
      post_([&] {
          Vec6d floor;
          floor << Vec3d::Constant(params.fusion.active.cov_floor_xyz),
              Vec3d::Constant(params.fusion.active.cov_floor_deg * kDeg);
          return floor;
      }(), params.fusion.active.cov_map_xyz, params.fusion.active.cov_floor_imu_xyz,
            params.fusion.active.cov_drift_tilt_deg * kDeg) {}

void Tracker::setMap(std::shared_ptr<const map::PriorMap> map, const NdtAligner* ndt) {
    map_ = std::move(map);
    ndt_.setTarget(ndt);
}

void Tracker::begin(const Scan& scan, const SE3d& T_map_lidar0, Frame& f) {
    f.scan = &scan;
    f.report = TrackReport{};
    TrackReport& rep = f.report;
    f.first = !have_prev_;
    f.prev = prev_;
    // Step 1: prediction.
    auto t0 = Clock::now();
    f.pre = imu::Preintegration(prev_.bias(), imu::ImuNoise{params_.imu.acc_noise, params_.imu.gyro_noise});
    if (f.first) {
        imu::ImuBias b;
        std::optional<double> tilt_deg;
        f.pred = predictFirst(scan, T_map_lidar0 * scan.T_imu_lidar.inverse(), sensors_, params_.loc.use_imu,
                              params_.imu, b, tilt_deg);
        if (tilt_deg)
            log_.logFmt(mrpt::system::LVL_INFO, "IMU at rest: gyro bias %.4f %.4f %.4f rad/s, tilt vs initial pose %.2f deg",
                        b.gyro.x(), b.gyro.y(), b.gyro.z(), *tilt_deg);
        f.start = fusion::FrameState{};
        f.start.setBias(b);
    } else {
        f.pred = predictMotion(prev_, prev_prev_, scan.t, sensors_, *variant_.fusion, params_.loc.use_imu, g_map_,
                               f.pre);
        f.start = prev_;
        f.start.setVelocity(f.pred.v);
    }
    f.start.t = scan.t;
    f.start.setPose(f.pred.T_map_imu);
    rep.used_imu = f.pred.used_imu;
    rep.T_map_lidar_pred = f.pred.T_map_imu * scan.T_imu_lidar;
    rep.ms.predict = msSince(t0);

    // Step 2: features.
    t0 = Clock::now();
    rep.deskewed =
        preproc_.run(scan, f.pred, prev_, sensors_, g_map_, reg_->traits().all_candidates, f.features);
    rep.points_raw = scan.size();
    rep.points_valid = f.features.valid.size();
    rep.candidates = f.features.candidates.size();
    rep.features = f.features.feature_idx.size();
    rep.ms.preprocess = msSince(t0);
}

bool Tracker::velocityUnknown(Frame& f, bool may_measure) {
    TrackReport& rep = f.report;
    const Scan& scan = *f.scan;
    // Unknown velocity (doc/localizer.md): the first frame, the second without IMU (no velocity
    // yet), and a constant-velocity prediction over a gap longer than max_cv_gap start coarse,
    // and their solved pose is not checked against the prediction (it may be far off, rightly);
    // without IMU, the last scan first measures the motion, and the frame is tracked from it.
    bool unknown = f.first || restart_ ||
                   (!f.pred.used_imu && !f.pred.from_odom &&
                    (!prev_prev_ || scan.t - prev_.t > params_.loc.max_cv_gap));
    if (unknown && !f.first && may_measure && !f.pred.used_imu && params_.loc.motion_from_last_scan &&
        !last_scan_points_.empty() && measureMotion(f)) {
        // Measured, not assumed: the frame is solved as a tracked one from the motion the last
        // scan gives, and checked against it.
        unknown = false;
        rep.motion_from_scan = true;
        f.start.setPose(f.pred.T_map_imu);
        rep.T_map_lidar_pred = f.pred.T_map_imu * scan.T_imu_lidar;
    }
    restart_ = false;
    return unknown;
}

FrameSolution Tracker::track(Frame& f, bool velocity_unknown) {
    FrameSolution sol;
    sol.state = f.start;
    sol.report = f.report;
    TrackReport& rep = sol.report;
    sol.corr = std::move(spare_corr_);
    sol.corr.reserve(f.features.pts_body.size());  // one correspondence per feature at most
    const imu::Preintegration* imu = f.pred.used_imu ? &f.pre : nullptr;
    const Registration::Traits how = reg_->traits();
    // A frame predicted from a motion the last frame confirmed may end its annealing early
    // (prediction_confirmed_ is false with settle_xyz = 0); with settle_after_scan also one whose
    // motion was measured against the last scan, when that frame was tracked to a sound end
    // (never after the first frame or a wide start: a small first step after a doubtful start
    // does not mean the start was right, doc/localizer.md).
    const bool after_scan =
        params_.loc.settle_after_scan && rep.motion_from_scan && last_sound_ && params_.loc.settle_xyz > 0;
    const bool may_settle = ((prediction_confirmed_ && !rep.motion_from_scan) || after_scan) && !velocity_unknown;
    trackedSolve(*reg_, f, sol, velocity_unknown && how.coarse_to_fine, imu, may_settle);
    if (velocity_unknown && how.coarse_to_fine && wantsSweepVelocity(f.pred) && !rep.diverged)
        sweepVelocity(f, f.pred, imu, sol);
    // Step 6: report.
    finish(f, f.pred, velocity_unknown, sol);
    if (how.joint && !rep.diverged)
        posterior(f, sol);
    else
        scanCovariance(sol);
    // How long the prediction alone has carried a translation axis the scan leaves weak, counted
    // from the first frame of that stretch whose position std passed what a navigation stack
    // tolerates (HealthMonitor, doc/health.md): a stretch the covariance holds within the
    // tolerance is not dead reckoning; one it has let go of stays so until the scan holds the
    // axis again, whatever the covariance says meanwhile (an end wall coming into view collapses
    // it before the solve has caught up).
    const double hold = 1.0 / std::pow(params_.health.max_sigma_xyz / 10.0, 2);
    bool blind = false;
    for (int k = 0; k < 3; ++k) blind |= rep.gamma[k] < params_.health.weak_gamma && !(rep.prior_weight[k] >= hold);
    if (!blind || rep.diverged) blind_since_.reset();
    else if (!blind_since_ && fusion::largestStd(rep.cov.topLeftCorner<3, 3>()) > params_.health.max_sigma_xyz)
        blind_since_ = f.scan->t;
    rep.dead_reckoning_s = blind_since_ ? f.scan->t - *blind_since_ : 0.0;
    return sol;
}

Tracker::EstimateWindow::EstimateWindow(const fusion::FrameState& prev, const fusion::FrameState& cur,
                                        const imu::Preintegration* imu, const LocalizerParams& params)
    : pv(prev), c(cur) {
    // The IMU chain as it really errs (ActiveFusionParams::estimate_imu_scale), not as the
    // solver's inflated noise would have it.
    const double s = params.fusion.active.estimate_imu_scale;
    if (imu) est_imu = imu->withNoiseScale(s);
    in.prev = &pv;
    in.cur = &c;
    in.setImu(est_imu ? &*est_imu : nullptr, params.imu, s);
}

void Tracker::trackedSolve(const Registration& reg, Frame& f, FrameSolution& sol, bool wide,
                           const imu::Preintegration* imu, bool may_settle) {
    // What the method's odom_alt fusion sees of this frame (odom_alt looked up once per solve).
    FrameFusion fusion(*variant_.fusion, params_.fusion, params_.risk,
                       odom_link_.frame(have_prev_, sol.state.T_map_imu(), f.prev.T_map_imu(), f.prev.t, sol.state.t));
    // What the estimate knows without odom_alt, carried from the last frame through the IMU
    // (fusion::EstimateInformation); the scan's is added at the risk step. Timed with it. Only
    // a joint solve reads it (its fusion's prior, the posterior): not ndt.
    if (reg.traits().joint) {
        const auto t_est = Clock::now();
        EstimateWindow w(f.prev, sol.state, imu, params_);
        sol.est_info = est_info_;
        sol.est_info->predict(w.in, params_.fusion);
        sol.report.ms.risk += msSince(t_est);
    }
    RegistrationProblem p = problem(f, SolvePurpose::Track, wide, imu);
    p.fusion = &fusion;
    p.may_settle = may_settle && !wide;
    p.without_voxel_planes = last_weak_ && !wide;
    reg.solve(p, sol);
}

RegistrationProblem Tracker::problem(Frame& f, SolvePurpose purpose, bool wide, const imu::Preintegration* imu) const {
    RegistrationProblem p;
    p.features = &f.features;
    p.map = map_.get();
    p.purpose = purpose;
    p.wide = wide;
    p.prev = &f.prev;
    p.imu = imu;
    if (purpose == SolvePurpose::Track) {
        p.prev_prior = prev_marginal_ ? &*prev_marginal_ : nullptr;
        p.marginalize = params_.fusion.window == "marginalized";
    }
    return p;
}

bool Tracker::wantsSweepVelocity(const Prediction& pred) const {
    const auto& fp = params_.features;
    return !pred.at_rest && params_.loc.sweep_velocity && fp.deskew && (pred.twist_from_imu || fp.deskew_without_imu);
}

FrameSolution Tracker::solveFrom(Frame& f, const fusion::FrameState& start, VerifyAs as, const TrackReport& base) {
    FrameSolution sol;
    sol.report = base;
    TrackReport& r = sol.report;
    r.diverged = false;
    r.diverged_reason = Divergence::None;
    r.converged = false;
    r.rounds = r.iterations = 0;
    sol.state = start;
    sol.state.t = f.scan->t;
    sol.corr.reserve(f.features.pts_body.size());  // one correspondence per feature at most
    const Prediction* frame_pred = as == VerifyAs::FirstFrame ? &f.pred : nullptr;
    // A hypothesis's or seed's solve on every k-th feature ([relocalization] hypothesis_features;
    // empty: on them all): it only has to find the basin.
    ScanFeatures few;
    if (frame_pred) {
        // ICP whatever the method: a seed is verified as the hypotheses are.
        trackedSolve(icp_, f, sol, true, nullptr);
        if (wantsSweepVelocity(*frame_pred) && !r.diverged) sweepVelocity(f, *frame_pred, nullptr, sol);
    } else {
        few = strided(f.features, params_.relocalization.hypothesis_features);
        const bool subset = !few.pts_body.empty();
        RegistrationProblem hp = problem(f, SolvePurpose::Hypothesis, true, nullptr);
        if (subset) hp.features = &few;
        icp_.solve(hp, sol);
        // A start seed is compared with the other seeds only: its fit is that of its own solve
        // (finish() below, on `few` where set); its basin is then verified as the first frame.
        if (as == VerifyAs::Hypothesis) {
            if (subset && !r.diverged) {
                // Settled in its basin on the few: polished on them all at the finest level (a
                // tracked solve's rounds), so that hypotheses in one basin end where the full
                // solve would put them and are not told apart as rivals (KITTI's global search:
                // 13 instead of 14-15 of 16 scans placed without the polish).
                const int rounds = r.rounds;
                r.converged = false;
                icp_.solve(problem(f, SolvePurpose::Hypothesis, false, nullptr), sol);
                r.rounds += rounds;
            }
            if (!icp_.association().voxel() || subset) {
                // Inliers measured as tracking measures them, so that the refined poses compare
                // with the frame's own solve (the two associations count inliers differently).
                const auto ta = Clock::now();
                associate(f.features.pts_body, sol.state.T_map_imu(), *map_, icp_.association(), sol.corr,
                          sol.stats);
                r.ms.associate += msSince(ta);
            }
        }
    }
    // No IMU prediction (a start's seed: the frame's own, from another pose): finished unchecked.
    Prediction p = frame_pred ? *frame_pred : Prediction{};
    p.T_map_imu = start.T_map_imu();
    if (!frame_pred && have_prev_ && !f.first) {
        // A hypothesis puts the body somewhere else, it does not change how the body moves: the
        // frame's predicted velocity (the IMU's; without IMU the last frame's) in the body.
        const SE3d& T_ref = f.pred.used_imu ? f.pred.T_map_imu : f.prev.T_map_imu();
        p.keep_v_body = T_ref.linear().transpose() * (f.pred.used_imu ? f.pred.v : f.prev.velocity());
    }
    finish(f, p, true, sol, as == VerifyAs::Seed && !few.pts_body.empty() ? &few : nullptr);
    scanCovariance(sol);  // a verified pose: its own scan's (doc/method.md §4)
    return sol;
}

void Tracker::finish(const Frame& f, const Prediction& pred, bool unchecked, FrameSolution& sol,
                     const ScanFeatures* features) const {
    const ScanFeatures& ft = features ? *features : f.features;
    TrackReport& rep = sol.report;
    const auto& lp = params_.loc;
    const Scan& scan = *f.scan;
    // Divergence by jump: the solved pose far from the prediction (not on the first frame, whose
    // "prediction" is the user's initial guess). An IMU prediction is trusted over such a
    // registration: the frame keeps the prediction (reason "jump_rejected"), so one bad match
    // cannot throw the velocity, and every later prediction, away.
    const bool jump = !unchecked && (translationDistance(sol.state.T_map_imu(), pred.T_map_imu) > lp.max_jump_xyz ||
                                     rotationAngle(sol.state.T_map_imu(), pred.T_map_imu) > lp.max_jump_deg * kDeg);
    const bool rejected = jump && pred.used_imu;
    if (rejected) {
        sol.state.setPose(pred.T_map_imu);
        sol.state.setVelocity(pred.v);
    }
    const SE3d T = sol.state.T_map_imu();
    // Quality at the estimate from the last association (re-querying the map here would cost
    // a whole association round; NDT has none, so it associates once).
    if (!reg_->traits().correspondences_at_solution || rejected) {
        const auto t0 = Clock::now();
        associate(ft.pts_body, T, *map_, icp_.association(), sol.corr, sol.stats);
        rep.ms.associate += msSince(t0);
    }
    rep.corr_plane = sol.stats.plane;
    rep.corr_line = sol.stats.line;
    rep.corr_point = sol.stats.point;
    rep.too_far = sol.stats.too_far;
    const InlierStats in = inlierStats(sol.corr, ft.pts_body.size(), T, lp.inlier_dist);
    rep.inlier_ratio = in.ratio;
    rep.residual_rms = in.rms;
    if (jump) {
        rep.diverged = true;
        rep.diverged_reason = rejected ? Divergence::JumpRejected : Divergence::Jump;
    } else if (!rep.diverged && in.ratio < lp.min_inlier_ratio) {
        rep.diverged = true;
        rep.diverged_reason = Divergence::Inliers;
    }
    if (pred.keep_v_body) {
        // A hypothesis from another pose: the difference from the last pose would carry the
        // search's correction as a speed (a 2.2 m correction at 10 Hz: 22 m/s), which the next
        // frame's IMU window then pours into the accelerometer bias (1.7 m/s^2 on the wander
        // sweep's L = 15 m seed 5, and 12 m off at the end of the next blind stretch).
        sol.state.setVelocity(T.linear() * *pred.keep_v_body);
    } else if (!pred.used_imu && !rejected) {
        // Without IMU the velocity is the finite difference of the estimates. The first frame's
        // is zero, or the sweep's (sweepVelocity: the IMU body's, in the map) when it was
        // estimated; the next frame then holds it by the fixed prior (the solve's marginal was
        // taken at zero velocity).
        const double dt = scan.t - f.prev.t;
        if (have_prev_ && dt > 0) {
            sol.state.setVelocity((T.translation() - f.prev.T_map_imu().translation()) / dt);
        } else if (!rep.sweep_velocity.isZero()) {
            const Mat3d R_il = scan.T_imu_lidar.linear();
            sol.state.setVelocity(T.linear() *
                                  (R_il * rep.sweep_velocity - pred.w_body.cross(scan.T_imu_lidar.translation())));
            sol.marginal.reset();
        } else {
            sol.state.setVelocity(Vec3d::Zero());
        }
    }
    rep.T_map_imu = T;
    rep.T_map_lidar = T * scan.T_imu_lidar;
    // The axes the scan holds weakly (the pose's covariance: posterior() or scanCovariance()).
    std::array<bool, 6> weak{};
    for (int k = 0; k < 6; ++k) weak[k] = rep.gamma[k] < params_.health.weak_gamma;
    rep.weak_axes = risk::axisLetters(weak);
    rep.velocity = sol.state.velocity();
    rep.bias = sol.state.bias();
}

void Tracker::end(const Frame& f, const fusion::FrameState& state, const FrameSolution& sol, const FrameReport& rep,
                  bool requested, bool pending, bool restart) {
    const Scan& scan = *f.scan;
    restart_ = restart;
    // A relocalized frame starts afresh: no velocity from the frames before it.
    prev_prev_ = have_prev_ && !restart_ ? std::optional<fusion::FrameState>(f.prev) : std::nullopt;
    prev_ = state;
    // Without IMU the next frame may need this scan to measure its motion (measureMotion): its
    // candidates, deskewed like its features, at the frame's final pose; not a lost one's.
    if (!rep.used_imu && params_.loc.motion_from_last_scan && rep.health != Health::Lost && !rep.diverged) {
        features::deskewPoints(scan.points, scan.rel_time, f.features.candidates, f.features.motion,
                               last_scan_points_);
        for (auto& p : last_scan_points_) p = (rep.T_map_lidar * p.cast<double>()).cast<float>();
        last_scan_origin_ = rep.T_map_lidar.translation().cast<float>();
    } else {
        last_scan_points_.clear();
    }
    // The marginal holds only for the state its solve produced: not after a divergence, a
    // recovery, a restart or any later change of the pose (jump rejection, eigen_remap).
    const bool own_solve = sol.marginal && !rep.diverged && !rep.recovered && !restart_ &&
                           (sol.marginal->T_ref.matrix() - state.T_map_imu().matrix()).cwiseAbs().maxCoeff() < 1e-9;
    prev_marginal_ = own_solve ? sol.marginal : std::nullopt;
    // The estimate's information and odom_alt's calibration go on from a frame tracked to its end.
    const bool tracked = !requested && !rep.diverged && !rep.recovered && !restart_ && rep.health != Health::Lost;
    last_sound_ = tracked && !f.first && rep.health == Health::Ok && rep.converged && !rep.coarse_start;
    prediction_confirmed_ = last_sound_ && !rep.motion_from_scan && rep.pred_dxyz < params_.loc.settle_xyz &&
                            rep.pred_ddeg < params_.loc.settle_deg;
    last_weak_ = tracked && params_.assoc.plane.wantsPointGeometry(rep.gamma);
    if (tracked) {
        if (sol.est_info) est_info_ = *sol.est_info;
        est_info_.commit(state, sol.scan_info);
    } else {
        est_info_.reset();
    }
    if (tracked && sol.post)
        post_.commit(*sol.post);
    else
        post_.reset();
    if (!tracked) blind_since_.reset();
    if (tracked && !f.first && variant_.fusion->usesOdomAlt()) odom_link_.frameDone(*variant_.fusion, sol, f.prev);
    if (prev_marginal_ && params_.fusion.marginal_scale != 1.0)
        prev_marginal_->sqrt_info *= std::sqrt(params_.fusion.marginal_scale);
    have_prev_ = have_prev_ || !pending;
}

}  // namespace superloc::localization
