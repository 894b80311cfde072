#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/features/deskew.h>
#include <superloc/imu/rest_init.h>
#include <superloc/localization/localizer.h>
#include <superloc/localization/ndt_registration.h>

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
constexpr size_t kMinCorrespondences = 10;
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
      preproc_(params.features) {
    assoc_.max_dist = params.loc.max_corr_dist;
    assoc_.voxel = params.loc.association == "voxel";
    assoc_.nearest_above_thickness = assoc_.voxel ? params.loc.voxel_nearest_above : 0.0;
    assoc_.plane_max_thickness = params.features.plane_max_thickness;
    assoc_.line_min_linearity = params.features.line_min_linearity;
    assoc_.max_fit_residual = params.loc.max_fit_residual;
    assoc_.point_weight = params.loc.point_weight;
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
    if (makeMethodVariant(methodFromString(params.loc.method), params.fusion, params.risk).registration == Registration::Ndt) {
        NdtParams np;
        np.resolution = params.loc.ndt_resolution;
        np.step_size = params.loc.ndt_step_size;
        np.epsilon = params.loc.ndt_epsilon;
        np.max_iterations = params.loc.ndt_max_iterations;
        p.ndt = std::make_unique<NdtRegistration>(p.map->points(), np);
    }
    if (params.relocalization.enabled) p.search = std::make_unique<reloc::GlobalSearch>(*p.map, params.global_search);
    return p;
}

void Localizer::setMap(PreparedMap&& prepared) {
    if (!prepared.map || prepared.map->size() == 0) throw ConfigError("Localizer: the prior map is empty");
    if (static_cast<bool>(prepared.ndt) != (variant_.registration == Registration::Ndt) ||
        static_cast<bool>(prepared.search) != params_.relocalization.enabled)
        throw ConfigError("Localizer::setMap: the map was prepared for other parameters");
    // The old search refers to the old map: replace it before the map it may outlive.
    search_ = std::move(prepared.search);
    ndt_ = std::move(prepared.ndt);
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
    const auto& lp = params_.loc;
    const bool from_hypothesis = kind == Solve::Hypothesis;
    const bool fused = kind == Solve::Track;  // odom_alt prior, IMU window
    const fusion::FrameState prev_saved = prev_;
    // What the method's odom_alt fusion sees of this frame (odom_alt looked up once per solve);
    // its pose is set to each round's association pose where the policy is asked.
    FusionFrame fusion_frame;
    if (fused) fusion_frame = fusionFrame(cur_.T_map_imu(), prev_saved.T_map_imu());
    if (fused) {
        // What the estimate knows without odom_alt, carried from the last frame through the IMU
        // (fusion::EstimateInformation); the scan's labels are added at the association below.
        fusion::FrameState p = prev_saved, c = cur_;
        fusion::FrameProblemInputs in;
        in.prev = &p;
        in.cur = &c;
        in.imu = pre;
        in.g_map = g_map_;
        in.acc_bias_rw = params_.imu.acc_bias_rw;
        in.gyro_bias_rw = params_.imu.gyro_bias_rw;
        est_info_.predict(in, params_.fusion);
    }
    const int rounds = wide ? lp.rounds_init : lp.rounds;
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
    const int n_levels = voxel ? map_->voxels().levels() : 1;
    // A hypothesis starts one level below the coarsest at most (1 m by default): the search's
    // refinement has brought it within a few decimetres, and the 2 m level's plane biases in
    // small rooms pushed right hypotheses away (simulated office: the right pose then lost to a
    // look-alike room).
    int level = voxel && wide ? (from_hypothesis ? std::min(1, n_levels - 1) : n_levels - 1) : 0;
    double radius = !voxel && wide ? lp.max_corr_dist_init : lp.max_corr_dist;
    int in_stage = 0;
    last_stats_ = {};
    corr_.clear();
    std::optional<fusion::RelativePosePrior> prior;
    for (int r = 0; r < rounds; ++r, ++in_stage) {
        // Step 3: associate at the current estimate (the prediction on round 0).
        const double scale = voxel ? std::pow(2.0, level) : 1.0;
        AssociationParams ap = assoc_;
        ap.voxel = voxel;
        ap.level = level;
        ap.max_dist = voxel ? lp.max_corr_dist * scale : radius;
        const double floor = params_.fusion.kernel_scale * scale;
        const double kernel =
            std::max(floor, voxel ? (wide ? 0.5 : 0.25) * map_->voxels().levelSize(level) * std::pow(0.5, in_stage)
                                  : 0.5 * radius * std::pow(0.5, in_stage));
        const bool finest = voxel ? level == 0 : radius <= lp.max_corr_dist;
        const SE3d T_before = cur_.T_map_imu();
        auto t0 = Clock::now();
        associate(features_.pts_body, T_before, *map_, ap, corr_, last_stats_);
        rep.ms.associate += msSince(t0);
        if (r == 0 || (voxel && level == 0 && in_stage == 0 && wide)) {
            // Step 4: alignment risk before the optimisation at this resolution (DESIGN §5): at the
            // predicted pose, and for a wide frame again when the finest level starts.
            t0 = Clock::now();
            const auto risk = risk::computeAlignmentRisk(corr_, T_before, T_imu_lidar_.translation(),
                                                         params_.risk);
            rep.setRisk(risk);
            if (fused) {
                // Where is the estimate weak without odom_alt? (doc/method.md §2)
                const Mat6d H = fusion::scanInformation(corr_, T_before, params_.fusion.scan_sigma);
                const double n = params_.risk.normal_noise_deg * kDeg;
                scan_info_ = fusion::informationAboveNoise(H, std::pow(std::sin(n), 2));
                Vec6d weak;
                weak << Vec3d::Constant(params_.risk.weak_sigma_xyz), Vec3d::Constant(params_.risk.weak_sigma_deg * kDeg);
                fusion_frame.scan = fusion::weakness(scan_info_, weak);
                fusion_frame.est = fusion::weakness(est_info_.information(scan_info_), weak);
                rep.scan_info = scan_info_.diagonal();
                rep.scan_sigma = fusion_frame.scan.sigma;
                rep.est_sigma = fusion_frame.est.sigma;
                rep.weak = fusion_frame.est.weak;
                frame_est_ = fusion_frame.est;
                frame_scan_ = fusion_frame.scan;
            }
            if (fused) {
                fusion_frame.T_map_imu = T_before;
                prior = variant_.fusion->prior(fusion_frame, risk);
            }
            rep.ms.risk += msSince(t0);
        }
        if (corr_.size() < kMinCorrespondences && !pre) {
            if (voxel && level > 0) {  // nothing at this level: try the next finer one
                --level;
                in_stage = -1;
                continue;
            }
            rep.diverged = true;
            rep.diverged_reason = "no_correspondences";
            break;
        }
        // Step 5: joint solve (paper eq. 12) with IRLS weights at the association pose.
        t0 = Clock::now();
        // The factor borrows the round's correspondences and gives them back at the end of the
        // round (no 2000-element copy per round; corr_ keeps its capacity).
        fusion::ScanFactor scan(std::move(corr_), params_.fusion.scan_sigma * scale);
        struct GiveBack {
            fusion::ScanFactor& f;
            std::vector<Correspondence>& v;
            ~GiveBack() { v = f.release(); }
        } give_back{scan, corr_};
        scan.setRobustWeights(T_before, kernel_, kernel);
        prev_ = prev_saved;
        fusion::FrameProblemInputs in;
        in.prev = &prev_;
        in.cur = &cur_;
        in.scan = scan.correspondences().size() >= kMinCorrespondences ? &scan : nullptr;
        in.imu = pre;
        in.g_map = g_map_;
        in.acc_bias_rw = params_.imu.acc_bias_rw;
        in.gyro_bias_rw = params_.imu.gyro_bias_rw;
        in.prior = prior;
        in.prev_prior = prev_marginal_ && fused ? &*prev_marginal_ : nullptr;
        // Only the last round's marginal is kept: ask for it on a round that can be the last
        // (finest resolution with the kernel at its floor, or the last allowed round).
        in.marginalize = params_.fusion.window == "marginalized" && fused &&
                         ((finest && kernel <= floor) || r == rounds - 1);
        const auto sum = fusion::solveFrame(in, params_.fusion);
        if (fused) cur_marginal_ = sum.marginal;
        rep.ms.solve += msSince(t0);
        rep.rounds = r + 1;
        rep.iterations += sum.iterations;
        rep.prior_used = prior.has_value();
        rep.final_level = level;
        if (!sum.usable) {
            rep.diverged = true;
            rep.diverged_reason = "solver";
            break;
        }
        if (fused) {  // the method's odom_alt fusion may amend the round's solution
            const SE3d T_solved = cur_.T_map_imu();
            fusion_frame.T_map_imu = T_before;
            const SE3d T_kept = variant_.fusion->afterRound(fusion_frame, T_before, scan, T_solved, rep);
            if (T_kept.matrix() != T_solved.matrix()) cur_.setPose(T_kept);
        }
        const SE3d T_after = cur_.T_map_imu();
        rep.last_step_xyz = translationDistance(T_before, T_after);
        rep.last_step_deg = rotationAngle(T_before, T_after) / kDeg;
        const bool small = translationDistance(T_before, T_after) < lp.converged_xyz * scale &&
                           rotationAngle(T_before, T_after) < lp.converged_deg * scale * kDeg;
        if (small && kernel <= floor) {
            if (finest) {
                rep.converged = true;
                break;
            }
            if (voxel)
                --level;
            else
                radius = std::max(lp.max_corr_dist, 0.7 * radius);
            in_stage = -1;
        }
    }
    if (voxel && level > 0 && !rep.diverged) {
        // The rounds ran out before the finest level: associate there once more so that the
        // frame's quality is measured at full resolution.
        AssociationParams ap = assoc_;
        ap.voxel = voxel;
        const auto t0 = Clock::now();
        associate(features_.pts_body, cur_.T_map_imu(), *map_, ap, corr_, last_stats_);
        rep.ms.associate += msSince(t0);
    }
    if (prior) rep.prior_weight = (prior->sqrt_info.transpose() * prior->sqrt_info).diagonal();
}

void Localizer::solveNdt(const SE3d& T_imu_lidar, const imu::Preintegration* pre, FrameReport& rep) {
    // The registration step is PCL's NDT from the predicted pose; everything else is shared.
    // The alignment risk is reported for ndt too (not used): correspondences at the prediction.
    auto ta = Clock::now();
    associate(features_.pts_body, cur_.T_map_imu(), *map_, assoc_, corr_, last_stats_);
    rep.ms.associate += msSince(ta);
    ta = Clock::now();
    const auto risk =
        risk::computeAlignmentRisk(corr_, cur_.T_map_imu(), T_imu_lidar.translation(), params_.risk);
    rep.setRisk(risk);
    rep.ms.risk += msSince(ta);
    const auto t0 = Clock::now();
    const SE3d guess = cur_.T_map_imu() * T_imu_lidar;
    const AlignResult a = ndt_->align(features_.ndt_source, guess);
    rep.rounds = 1;
    rep.iterations = a.iterations;
    rep.converged = a.converged;
    const SE3d T_ndt = a.T_target_source * T_imu_lidar.inverse();
    cur_.setPose(T_ndt);
    if (pre) {
        // Loosely coupled, like hdl_localization's filter: the NDT pose as a measurement
        // (sigma scan_sigma, 0.5 deg) with the IMU factor, for velocity and biases.
        Mat6d w = Mat6d::Zero();
        w.diagonal().head<3>().setConstant(1.0 / params_.fusion.scan_sigma);
        w.diagonal().tail<3>().setConstant(1.0 / (0.5 * kDeg));
        fusion::FrameProblemInputs in;
        in.prev = &prev_;
        in.cur = &cur_;
        in.imu = pre;
        in.g_map = g_map_;
        in.acc_bias_rw = params_.imu.acc_bias_rw;
        in.gyro_bias_rw = params_.imu.gyro_bias_rw;
        in.cur_pose_prior = std::make_pair(T_ndt, w);
        in.prev_prior = prev_marginal_ ? &*prev_marginal_ : nullptr;
        in.marginalize = params_.fusion.window == "marginalized";
        const auto sum = fusion::solveFrame(in, params_.fusion);
        cur_marginal_ = sum.marginal;
        rep.iterations += sum.iterations;
    }
    rep.ms.solve += msSince(t0);
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
    if (variant_.registration == Registration::Ndt || rejected) {
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
    preproc_.run(scan, pred, prev_, sensors_, g_map_, variant_.registration == Registration::Ndt, features_, rep);
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
    rep.coarse_start = velocity_unknown && variant_.registration != Registration::Ndt;
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
        if (variant_.registration == Registration::Ndt) {
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
