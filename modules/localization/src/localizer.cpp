#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/features/deskew.h>
#include <superloc/imu/rest_init.h>
#include <superloc/localization/localizer.h>
#include <superloc/localization/ndt_aligner.h>
#include <superloc/localization/frame_fusion.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>

namespace superloc::localization {

void FrameReport::setRisk(const risk::RiskReport& r) {
    gamma = r.gamma;
    degenerate = r.degenerate;
    degenerate_axes = risk::degenerateAxes(r);
    flags_labels1 = risk::axisLetters(r.rules.labels1);
    flags_labels2 = risk::axisLetters(r.rules.labels2);
    flags_eigen = risk::axisLetters(r.rules.eigen);
    hessian_eigenvalues = r.weight_sum > 0 ? Vec6d(r.eigenvalues / r.weight_sum) : Vec6d::Zero();
    translation_eigenvalues = r.translation_eigenvalues;
    weakest_translation = r.weakest_translation;
}

namespace {
using Clock = SteadyClock;
double threadCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}
}  // namespace

Localizer::Localizer(const LocalizerParams& params, std::shared_ptr<const map::PriorMap> map)
    : mrpt::system::COutputLogger("Localizer"),
      params_(params),
      method_(methodFromString(params.loc.method)),
      variant_(makeMethodVariant(method_, params.fusion, params.risk)),
      health_(params.health),
      map_(std::move(map)),
      kernel_(fusion::robustKernelFromString(params.fusion.robust_kernel)),
      g_map_(0, 0, -params.imu.gravity),
      preproc_(params.features),
      assoc_(trackingAssociation(params.loc, params.features)),
      icp_(params),
      ndt_reg_(params, assoc_),
      odom_link_(sensors_, *variant_.fusion, params_.fusion, method_, *this) {
    setMap(std::move(map_));
}

PreparedMap::PreparedMap() = default;
PreparedMap::PreparedMap(PreparedMap&&) noexcept = default;
PreparedMap& PreparedMap::operator=(PreparedMap&&) noexcept = default;
PreparedMap::~PreparedMap() = default;

PreparedMap Localizer::prepareMap(const LocalizerParams& params, std::shared_ptr<const map::PriorMap> map) {
    if (!map || map->size() == 0) throw ConfigError("Localizer: the prior map is empty");
    PreparedMap p;
    p.map = std::move(map);
    if (makeMethodVariant(methodFromString(params.loc.method), params.fusion, params.risk).registration == RegistrationKind::Ndt) {
        NdtParams np;
        np.resolution = params.loc.ndt_resolution;
        np.step_size = params.loc.ndt_step_size;
        np.epsilon = params.loc.ndt_epsilon;
        np.max_iterations = params.loc.ndt_max_iterations;
        p.ndt = std::make_unique<NdtAligner>(p.map->points(), np);
    }
    if (params.relocalization.enabled) p.search = std::make_unique<reloc::GlobalSearch>(*p.map, params.global_search);
    return p;
}

void Localizer::setMap(PreparedMap&& prepared) {
    if (!prepared.map || prepared.map->size() == 0) throw ConfigError("Localizer: the prior map is empty");
    if (static_cast<bool>(prepared.ndt) != (variant_.registration == RegistrationKind::Ndt) ||
        static_cast<bool>(prepared.search) != params_.relocalization.enabled)
        throw ConfigError("Localizer::setMap: the map was prepared for other parameters");
    // The old search refers to the old map: replace it before the map it may outlive.
    search_ = std::move(prepared.search);
    ndt_ = std::move(prepared.ndt);
    ndt_reg_.setTarget(ndt_.get());
    map_ = std::move(prepared.map);
    if (search_) search_->setMinLoggingLevel(getMinLoggingLevel());
}

void Localizer::setMap(std::shared_ptr<const map::PriorMap> map) { setMap(prepareMap(params_, std::move(map))); }

void Localizer::relocalize(const std::optional<reloc::SearchRegion>& region) {
    if (!search_) throw ConfigError("relocalize(): [relocalization] enabled = false");
    reloc_pending_ = true;
    reloc_region_ = region;
}

Localizer::~Localizer() = default;

void Localizer::setInitialPose(const SE3d& T_map_lidar) { initial_T_map_lidar_ = T_map_lidar; }

void Localizer::addImu(const ImuSample& s) { sensors_.addImu(s); }

void Localizer::addOdomAlt(const PoseStamped& p) { sensors_.addOdomAlt(p); }

void Localizer::solveIcp(const imu::Preintegration* pre, bool wide, FrameReport& rep, Solve kind) {
    const bool fused = kind == Solve::Track;  // odom_alt prior, IMU window
    FrameSolution sol;
    sol.state = cur_;
    sol.corr = std::move(corr_);
    RegistrationProblem p;
    p.features = &features_;
    p.map = map_.get();
    p.purpose = kind == Solve::Track ? SolvePurpose::Track : kind == Solve::Hypothesis ? SolvePurpose::Hypothesis
                                                                                       : SolvePurpose::LastScan;
    p.wide = wide;
    p.prev = &prev_;
    p.imu = pre;
    std::optional<FrameFusion> fusion;
    if (fused) {
        // What the method's odom_alt fusion sees of this frame (odom_alt looked up once per solve).
        fusion.emplace(*variant_.fusion, params_.fusion, params_.risk,
                       odom_link_.frame(have_prev_, cur_.T_map_imu(), prev_.T_map_imu(), prev_.t, cur_.t));
        // What the estimate knows without odom_alt, carried from the last frame through the IMU
        // (fusion::EstimateInformation); the scan's labels are added at the association.
        fusion::FrameState pv = prev_, c = cur_;
        fusion::FrameProblemInputs in;
        in.prev = &pv;
        in.cur = &c;
        in.imu = pre;
        in.g_map = g_map_;
        in.acc_bias_rw = params_.imu.acc_bias_rw;
        in.gyro_bias_rw = params_.imu.gyro_bias_rw;
        sol.est_info = est_info_;
        sol.est_info->predict(in, params_.fusion);
        p.prev_prior = prev_marginal_ ? &*prev_marginal_ : nullptr;
        p.marginalize = params_.fusion.window == "marginalized";
        p.fusion = &*fusion;
    }
    icp_.solve(p, sol, rep);
    cur_ = sol.state;
    corr_ = std::move(sol.corr);
    last_stats_ = sol.stats;
    if (fused) {
        cur_marginal_ = sol.marginal;
        est_info_ = *sol.est_info;
        scan_info_ = sol.scan_info;
        frame_est_ = sol.est_weak;
        frame_scan_ = sol.scan_weak;
    }
}

void Localizer::solveNdt(const SE3d&, const imu::Preintegration* pre, FrameReport& rep) {
    FrameSolution sol;
    sol.state = cur_;
    sol.corr = std::move(corr_);
    sol.marginal = cur_marginal_;
    RegistrationProblem p;
    p.features = &features_;
    p.map = map_.get();
    p.prev = &prev_;
    p.imu = pre;
    p.prev_prior = prev_marginal_ ? &*prev_marginal_ : nullptr;
    p.marginalize = params_.fusion.window == "marginalized";
    ndt_reg_.solve(p, sol, rep);
    cur_ = sol.state;
    corr_ = std::move(sol.corr);
    last_stats_ = sol.stats;
    cur_marginal_ = sol.marginal;
}

void Localizer::finish(const Scan& scan, const Prediction& pred, bool unchecked, FrameReport& rep) {
    const auto& lp = params_.loc;
    // Divergence by jump: the solved pose far from the prediction (not on the first frame, whose
    // "prediction" is the user's initial guess). An IMU prediction is trusted over such a
    // registration: the frame keeps the prediction (reason "jump_rejected"), so one bad match
    // cannot throw the velocity, and every later prediction, away.
    const bool jump = !unchecked && (translationDistance(cur_.T_map_imu(), pred.T_map_imu) > lp.max_jump_xyz ||
                                 rotationAngle(cur_.T_map_imu(), pred.T_map_imu) > lp.max_jump_deg * kDeg);
    const bool rejected = jump && pred.used_imu;
    if (rejected) {
        cur_.setPose(pred.T_map_imu);
        cur_.setVelocity(pred.v);
    }
    const SE3d T = cur_.T_map_imu();
    // Quality at the estimate from the last association (re-querying the map here would cost
    // a whole association round; NDT has none, so it associates once).
    if (variant_.registration == RegistrationKind::Ndt || rejected) {
        const auto t0 = Clock::now();
        associate(features_.pts_body, T, *map_, assoc_, corr_, last_stats_);
        rep.ms.associate += msSince(t0);
    }
    rep.corr_plane = last_stats_.plane;
    rep.corr_line = last_stats_.line;
    rep.corr_point = last_stats_.point;
    rep.too_far = last_stats_.too_far;
    const InlierStats in = inlierStats(corr_, features_.pts_body.size(), T, lp.inlier_dist);
    rep.inlier_ratio = in.ratio;
    rep.residual_rms = in.rms;
    if (jump) {
        rep.diverged = true;
        rep.diverged_reason = rejected ? "jump_rejected" : "jump";
    } else if (!rep.diverged && in.ratio < lp.min_inlier_ratio) {
        rep.diverged = true;
        rep.diverged_reason = "inliers";
    }
    if (!pred.used_imu && !rejected) {
        // Without IMU the velocity is the finite difference of the estimates. The first frame's
        // is zero, or the sweep's (solveSweepVelocity: the IMU body's, in the map) when it was
        // estimated; the next frame then holds it by the fixed prior (the solve's marginal was
        // taken at zero velocity).
        const double dt = scan.t - prev_.t;
        if (have_prev_ && dt > 0) {
            cur_.setVelocity((T.translation() - prev_.T_map_imu().translation()) / dt);
        } else if (!rep.sweep_velocity.isZero()) {
            const Mat3d R_il = scan.T_imu_lidar.linear();
            cur_.setVelocity(T.linear() * (R_il * rep.sweep_velocity - pred.w_body.cross(scan.T_imu_lidar.translation())));
            cur_marginal_.reset();
        } else {
            cur_.setVelocity(Vec3d::Zero());
        }
    }
    rep.T_map_imu = T;
    rep.T_map_lidar = T * scan.T_imu_lidar;
    rep.velocity = cur_.velocity();
    rep.bias = cur_.bias();
    last_T_map_lidar_ = rep.T_map_lidar;
}

const std::vector<Vec3f>& Localizer::mapPoints(const Scan& scan, double voxel) {
    // The valid points of the last scan, voxel-selected, deskewed like its features, in the map
    // frame at its estimate.
    map_selector_.select(scan.points, features_.valid, static_cast<float>(voxel), map_idx_);
    features::deskewPoints(scan.points, scan.rel_time, map_idx_, features_.motion, map_points_);
    for (auto& p : map_points_) p = (last_T_map_lidar_ * p.cast<double>()).cast<float>();
    return map_points_;
}

bool Localizer::wantsSweepVelocity(const Prediction& pred) const {
    const auto& fp = params_.features;
    return !pred.at_rest && params_.loc.sweep_velocity && fp.deskew && (pred.twist_from_imu || fp.deskew_without_imu);
}

FrameReport Localizer::process(const Scan& scan) {
    const auto t_start = Clock::now();
    const double cpu_start = threadCpuMs();
    FrameReport rep;
    rep.index = frames_++;
    rep.t = scan.t;
    const bool first = !have_prev_;
    cur_marginal_.reset();
    scan_info_.setZero();
    frame_est_ = frame_scan_ = {};
    T_imu_lidar_ = scan.T_imu_lidar;

    // Step 1: prediction.
    auto t0 = Clock::now();
    imu::Preintegration pre(prev_.bias(), imu::ImuNoise{params_.imu.acc_noise, params_.imu.gyro_noise});
    Prediction pred;
    if (first) {
        imu::ImuBias b;
        std::optional<double> tilt_deg;
        pred = predictFirst(scan, initial_T_map_lidar_.value_or(SE3d::Identity()) * scan.T_imu_lidar.inverse(), sensors_,
                            params_.loc.use_imu, params_.imu, b, tilt_deg);
        if (tilt_deg)
            MRPT_LOG_INFO_FMT("IMU at rest: gyro bias %.4f %.4f %.4f rad/s, tilt vs initial pose %.2f deg", b.gyro.x(),
                              b.gyro.y(), b.gyro.z(), *tilt_deg);
        cur_ = fusion::FrameState{};
        cur_.setBias(b);
    } else {
        pred = predictMotion(prev_, prev_prev_, scan.t, sensors_, params_.loc.use_imu, g_map_, pre);
        cur_ = prev_;
        cur_.setVelocity(pred.v);
    }
    cur_.t = scan.t;
    cur_.setPose(pred.T_map_imu);
    rep.used_imu = pred.used_imu;
    rep.T_map_lidar_pred = pred.T_map_imu * scan.T_imu_lidar;
    rep.ms.predict = msSince(t0);

    // Step 2: features.
    t0 = Clock::now();
    preproc_.run(scan, pred, prev_, sensors_, g_map_, variant_.registration == RegistrationKind::Ndt, features_, rep);
    rep.ms.preprocess = msSince(t0);

    // Steps 3-5: association, risk, solve.
    const auto& lp = params_.loc;
    // Unknown velocity (doc/localizer.md): the first frame, the second without IMU (no velocity
    // yet), and a constant-velocity prediction over a gap longer than max_cv_gap start coarse,
    // and their solved pose is not checked against the prediction (it may be far off, rightly);
    // without IMU, the last scan first measures the motion, and the frame is tracked from it.
    bool velocity_unknown =
        first || restart_ || (!pred.used_imu && (!prev_prev_ || scan.t - prev_.t > lp.max_cv_gap));
    const bool requested = reloc_pending_ || !hypotheses_.empty();
    if (velocity_unknown && !first && !requested && !pred.used_imu && lp.motion_from_last_scan &&
        !last_scan_points_.empty() && motionFromLastScan(pred, rep)) {
        // Measured, not assumed: the frame is solved as a tracked one from the motion the last
        // scan gives, and checked against it.
        velocity_unknown = false;
        rep.motion_from_scan = true;
        cur_.setPose(pred.T_map_imu);
        rep.T_map_lidar_pred = pred.T_map_imu * scan.T_imu_lidar;
    }
    restart_ = false;
    rep.coarse_start = velocity_unknown && variant_.registration != RegistrationKind::Ndt;
    if (requested) {
        // relocalize() (e.g. --initial-pose auto): this scan is localized by the search alone.
        // Until a pose is accepted, every scan searches again, or, after an ambiguous search,
        // tracks its candidates (doc/relocalization.md §4); a lost frame's candidates likewise.
        rep.diverged = true;
        rep.diverged_reason = "no_pose";
        const auto& rp = params_.relocalization;
        if (!hypotheses_.empty()) refineCandidates(scan, rep);
        const bool tracking = !hypotheses_.empty();
        RelocOutcome o = RelocOutcome::None;
        if (!tracking || (rp.track_search_every > 0 && candidates_age_ % rp.track_search_every == 0)) {
            // A fresh search, where relocalize() asked or a lost frame looks; while candidates are
            // tracked, its hypotheses join them (and its winner must beat them too).
            std::optional<reloc::SearchRegion> region = reloc_region_;
            if (!reloc_pending_) {
                rep.health = Health::Lost;
                region = lostRegion(scan, lost_run_ + 1);
            }
            o = runRelocalization(scan, pred, region ? &*region : nullptr, rep);
        }
        if (tracking && o != RelocOutcome::Accepted) o = decideCandidates(scan, rep);
        if (o == RelocOutcome::Accepted) reloc_pending_ = false, doubt_ = false, hypotheses_.clear();
    } else {
        if (variant_.registration == RegistrationKind::Ndt) {
            solveNdt(scan.T_imu_lidar, pred.used_imu ? &pre : nullptr, rep);
        } else {
            solveIcp(pred.used_imu ? &pre : nullptr, velocity_unknown, rep);
            if (velocity_unknown && wantsSweepVelocity(pred) && !rep.diverged)
                solveSweepVelocity(scan, pred, pred.used_imu ? &pre : nullptr, rep);
        }
        // Step 6: report and state update.
        finish(scan, pred, velocity_unknown, rep);
    }
    rep.imu_drift_deg = requested ? 0.0 : health_.imuDrift(rep);
    assess(rep);
    // A given start is checked within its uncertainty (localizer_relocalize.cpp).
    if (first && !requested && initial_T_map_lidar_ && search_ && rep.health != Health::Lost)
        verifyStart(scan, pred, rep);
    // Step 7 (localizer_relocalize.cpp): a lost or doubtful frame searches the map (unless this
    // frame was the search's already), then the state carried to the next frame.
    recoverIfLost(scan, pred, !requested, rep);
    updateTrackingState(scan, pred, rep);
    const fusion::FrameState frame_prev = prev_;  // the state this frame was solved from
    // A relocalized frame starts afresh: no velocity from the frames before it.
    prev_prev_ = have_prev_ && !restart_ ? std::optional<fusion::FrameState>(prev_) : std::nullopt;
    prev_ = cur_;
    // Without IMU the next frame may need this scan to measure its motion (motionFromLastScan):
    // its candidates, deskewed like its features, at the frame's final pose; not a lost one's.
    if (!rep.used_imu && params_.loc.motion_from_last_scan && rep.health != Health::Lost && !rep.diverged) {
        features::deskewPoints(scan.points, scan.rel_time, features_.candidates, features_.motion, last_scan_points_);
        for (auto& p : last_scan_points_) p = (rep.T_map_lidar * p.cast<double>()).cast<float>();
        last_scan_origin_ = rep.T_map_lidar.translation().cast<float>();
    } else {
        last_scan_points_.clear();
    }
    // The marginal holds only for the state its solve produced: not after a divergence, a
    // recovery, a restart or any later change of the pose (jump rejection, eigen_remap).
    const bool own_solve = cur_marginal_ && !rep.diverged && !rep.recovered && !restart_ &&
                           (cur_marginal_->T_ref.matrix() - cur_.T_map_imu().matrix()).cwiseAbs().maxCoeff() < 1e-9;
    prev_marginal_ = own_solve ? cur_marginal_ : std::nullopt;
    // The estimate's information and odom_alt's calibration go on from a frame tracked to its end.
    const bool tracked = !requested && !rep.diverged && !rep.recovered && !restart_ && rep.health != Health::Lost;
    if (tracked)
        est_info_.commit(cur_, scan_info_);
    else
        est_info_.reset();
    if (tracked && !first && variant_.fusion->usesOdomAlt()) {
        FusionFrame f;
        f.T_map_imu = cur_.T_map_imu();
        f.T_prev_map_imu = frame_prev.T_map_imu();
        f.odom_delta = sensors_.odomAltDelta(frame_prev.t, cur_.t);
        f.est = frame_est_;
        f.scan = frame_scan_;
        variant_.fusion->frameDone(f, rep);
    }
    if (prev_marginal_ && params_.fusion.marginal_scale != 1.0)
        prev_marginal_->sqrt_info *= std::sqrt(params_.fusion.marginal_scale);
    have_prev_ = have_prev_ || !reloc_pending_;
    sensors_.forgetBefore(scan.t);
    rep.ms.total = msSince(t_start);
    rep.ms.total_cpu = threadCpuMs() - cpu_start;
    return rep;
}

}  // namespace superloc::localization
