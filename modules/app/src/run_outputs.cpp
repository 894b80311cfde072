#include <superloc/io/json_file.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>
#include <superloc/app/report_plots.h>
#include <superloc/app/run_outputs.h>
#include <superloc/core/se3.h>
#include <superloc/eval/timing.h>
#include <superloc/eval/trajectory_metrics.h>
#include <superloc/fusion/pose_posterior.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace superloc::app {

std::string framesCsvHeader() {
    return "t,x,y,z,qx,qy,qz,qw,gamma_x,gamma_y,gamma_z,gamma_roll,gamma_pitch,gamma_yaw,"
           "degenerate,prior_used,ms_total,"
           "index,inlier_ratio,residual_rms,points_raw,points_valid,candidates,features,"
           "corr_plane,corr_line,corr_point,too_far,rounds,iterations,converged,diverged,"
           "diverged_reason,used_imu,deskewed,"
           "prior_w_x,prior_w_y,prior_w_z,prior_w_roll,prior_w_pitch,prior_w_yaw,vx,vy,vz,"
           "ms_predict,ms_preprocess,ms_associate,ms_risk,ms_solve,ms_total_cpu,"
           "hess_eig_1,hess_eig_2,hess_eig_3,hess_eig_4,hess_eig_5,hess_eig_6,"
           "trans_eig_1,trans_eig_2,trans_eig_3,weak_t_x,weak_t_y,weak_t_z,recovered,"
           "health,health_reason,inlier_reference,pred_dxyz,pred_ddeg,"
           "reloc_mode,reloc_trigger,reloc_result,reloc_detail,reloc_hypotheses,reloc_verified,reloc_ms,last_step_xyz,last_step_deg,"
           "reloc_candidates,reloc_evidence_ratio,flags_labels1,flags_labels2,flags_eigen,start,imu_drift_deg,"
           "bias_ax,bias_ay,bias_az,bias_gx,bias_gy,bias_gz,"
           "scan_info_x,scan_info_y,scan_info_z,scan_info_roll,scan_info_pitch,scan_info_yaw,"
           "scan_sigma_x,scan_sigma_y,scan_sigma_z,scan_sigma_roll,scan_sigma_pitch,scan_sigma_yaw,"
           "est_sigma_x,est_sigma_y,est_sigma_z,est_sigma_roll,est_sigma_pitch,est_sigma_yaw,"
           "weak_axes,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,sigma_roll,sigma_pitch,sigma_yaw,dead_reckoning_s";
}

Mat6d reportedCovariance(const localization::FrameReport& r, const SE3d& T) {
    return fusion::toReported(r.cov, r.T_map_imu, r.T_map_imu.inverse() * T);
}

std::string framesCsvLine(const localization::FrameReport& r, const SE3d& T) {
    const Eigen::Quaterniond q(T.linear());
    const Vec3d p = T.translation();
    char buf[1024];
    int n = std::snprintf(buf, sizeof(buf), "%.9f,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f", r.t, p.x(), p.y(),
                          p.z(), q.x(), q.y(), q.z(), q.w());
    std::string s(buf, static_cast<size_t>(n));
    const auto add = [&s, &buf](const char* fmt, auto v) {
        const int k = std::snprintf(buf, sizeof(buf), fmt, v);
        s += ',';
        s.append(buf, static_cast<size_t>(k));
    };
    for (int k = 0; k < 6; ++k) add("%.4f", r.gamma[k]);
    s += ',' + r.degenerate_axes;
    add("%d", r.prior_used ? 1 : 0);
    add("%.3f", r.ms.total);
    add("%zu", r.index);
    add("%.4f", r.inlier_ratio);
    add("%.4f", r.residual_rms);
    for (size_t v : {r.points_raw, r.points_valid, r.candidates, r.features, r.corr_plane, r.corr_line,
                     r.corr_point, r.too_far})
        add("%zu", v);
    add("%d", r.rounds);
    add("%d", r.iterations);
    add("%d", r.converged ? 1 : 0);
    add("%d", r.diverged ? 1 : 0);
    s += ',';
    s += localization::divergenceName(r.diverged_reason);
    add("%d", r.used_imu ? 1 : 0);
    add("%d", r.deskewed ? 1 : 0);
    for (int k = 0; k < 6; ++k) add("%.6g", r.prior_weight[k]);
    for (int k = 0; k < 3; ++k) add("%.4f", r.velocity[k]);
    for (double v : {r.ms.predict, r.ms.preprocess, r.ms.associate, r.ms.risk, r.ms.solve, r.ms.total_cpu})
        add("%.3f", v);
    for (int k = 0; k < 6; ++k) add("%.6g", r.hessian_eigenvalues[k]);
    for (int k = 0; k < 3; ++k) add("%.5f", r.translation_eigenvalues[k]);
    for (int k = 0; k < 3; ++k) add("%.5f", r.weakest_translation[k]);
    add("%d", r.recovered ? 1 : 0);
    s += ',';
    s += localization::healthName(r.health);
    s += ',' + r.health_reason;
    add("%.4f", r.inlier_reference);
    add("%.4f", r.pred_dxyz);
    add("%.3f", r.pred_ddeg);
    std::string detail = r.reloc.detail;  // free text: no commas in a CSV cell
    std::replace(detail.begin(), detail.end(), ',', ';');
    s += ',' + r.reloc.mode + ',' + r.reloc.trigger + ',' + localization::relocOutcomeName(r.reloc.outcome) + ',' + detail;
    add("%d", r.reloc.hypotheses);
    add("%d", r.reloc.verified);
    add("%.2f", r.reloc.search_ms + r.reloc.verify_ms);
    add("%.5f", r.last_step_xyz);
    add("%.4f", r.last_step_deg);
    add("%d", r.reloc.candidates);
    add("%.4f", r.reloc.evidence_ratio);
    s += ',' + r.flags_labels1 + ',' + r.flags_labels2 + ',' + r.flags_eigen;
    s += r.motion_from_scan ? ",scan" : r.coarse_start ? ",wide" : ",tracked";
    add("%.3f", r.imu_drift_deg);
    for (int k = 0; k < 3; ++k) add("%.5f", r.bias.acc[k]);
    for (int k = 0; k < 3; ++k) add("%.6f", r.bias.gyro[k]);
    for (int k = 0; k < 6; ++k) add("%.6g", r.scan_info[k]);
    for (int k = 0; k < 6; ++k) add("%.6g", r.scan_sigma[k]);
    for (int k = 0; k < 6; ++k) add("%.6g", r.est_sigma[k]);
    s += ',' + r.weak_axes;
    // The pose's covariance: position in the map frame [m^2], rotation std about the reported
    // frame's own axes [deg] (doc/localizer.md, Outputs).
    const Mat6d C = reportedCovariance(r, T);
    for (const auto& [i, j] : {std::pair{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}}) add("%.6g", C(i, j));
    const Mat3d R = T.linear();
    const Mat3d Crot = R.transpose() * C.bottomRightCorner<3, 3>() * R;
    for (int k = 0; k < 3; ++k) add("%.5g", std::sqrt(std::max(0.0, Crot(k, k))) / kDeg);
    add("%.2f", r.dead_reckoning_s);
    return s;
}

RunOutputs::RunOutputs(const std::string& dir, double map_voxel, bool report)
    : dir_(dir), voxel_(static_cast<float>(map_voxel)) {
    if (report) report_.emplace();
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw std::runtime_error(dir + ": cannot create output folder (" + ec.message() + ")");
    const std::string csv = (std::filesystem::path(dir) / "frames.csv").string();
    csv_.open(csv);
    if (!csv_) throw std::runtime_error(csv + ": cannot open for writing");
    csv_ << framesCsvHeader() << '\n' << std::flush;
    tum_ = std::make_unique<io::TumWriter>((std::filesystem::path(dir) / "trajectory.tum").string(),
                                           "superloc-localize: t x y z qx qy qz qw");
    const std::string cov = (std::filesystem::path(dir) / "trajectory_cov.txt").string();
    cov_.open(cov);
    if (!cov_) throw std::runtime_error(cov + ": cannot open for writing");
    cov_ << "# superloc-localize: t c00 c01 ... c55: the 6x6 covariance of trajectory.tum's pose at t, row-major,\n"
            "# geometry_msgs/PoseWithCovariance's convention: (x y z) in the map frame [m], rotation about the\n"
            "# map's fixed x y z axes [rad] (doc/localizer.md, Outputs)\n"
         << std::flush;
}

RunOutputs::~RunOutputs() = default;

void RunOutputs::addFrame(const localization::FrameReport& r, const SE3d& T, const std::vector<Vec3f>& map_points) {
    tum_->write(r.t, T);
    csv_ << framesCsvLine(r, T) << '\n' << std::flush;
    const Mat6d C = reportedCovariance(r, T);
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.9f", r.t);
    cov_ << buf;
    for (int i = 0; i < 36; ++i) {
        std::snprintf(buf, sizeof(buf), " %.9g", C(i / 6, i % 6));
        cov_ << buf;
    }
    cov_ << '\n' << std::flush;
    if (report_) report_->addFrame(r, T);
    for (const auto& p : map_points) {
        if (voxel_ <= 0 || occupied_.insert(voxelKey(p, voxel_))) map_.push_back(p);
    }
}

void RunTally::addFrame(const localization::FrameReport& r, const SE3d& T, RunSummary& s) {
    est_.push_back(KeptPose{r.t, T.linear(), T.translation()});
    ms_.push_back(r.ms.total);
    cpu_.push_back(r.ms.total_cpu);
    stage_[0].push_back(r.ms.predict), stage_[1].push_back(r.ms.preprocess);
    stage_[2].push_back(r.ms.associate), stage_[3].push_back(r.ms.risk), stage_[4].push_back(r.ms.solve);
    s.frames++;
    s.diverged += r.diverged;
    s.converged += r.converged;
    s.used_imu += r.used_imu;
    s.with_prior += r.prior_used;
    s.recovered += r.recovered;
    s.health[static_cast<size_t>(r.health)]++;
    if (r.health != localization::Health::Lost && r.cov.trace() > 0) {
        // The pose's largest std (doc/method.md §4) over the run, frames not lost.
        sigma_xyz_.push_back(fusion::largestStd(r.cov.topLeftCorner<3, 3>()));
        sigma_deg_.push_back(fusion::largestStd(r.cov.bottomRightCorner<3, 3>()) / kDeg);
    }
    const bool flagged = !r.degenerate_axes.empty();
    s.flagged += flagged;
    s.flagged_without_prior += flagged && !r.prior_used;
    for (int k = 0; k < 6; ++k) s.flagged_axis[k] += r.degenerate[k];
}

void RunTally::addGroundTruth(const PoseStamped& p) { gt_.push_back(KeptPose{p.t, p.pose.linear(), p.pose.translation()}); }

Trajectory RunTally::trajectoryOf(const std::vector<KeptPose>& kept) {
    Trajectory out(kept.size());
    for (size_t i = 0; i < kept.size(); ++i) {
        out[i].t = kept[i].t;
        out[i].pose.linear() = kept[i].R;
        out[i].pose.translation() = kept[i].p;
    }
    return out;
}

void RunTally::fill(RunSummary& s) const {
    const eval::TimingStats wall = eval::timingStats(ms_);
    s.ms_median = wall.median_ms;
    s.ms_p95 = wall.p95_ms;
    s.ms_mean = wall.mean_ms;
    s.fps = wall.fps;
    s.cpu_ms_median = eval::median(cpu_);
    for (const auto* v : {&sigma_xyz_, &sigma_deg_}) {
        auto& out = v == &sigma_xyz_ ? s.sigma_xyz : s.sigma_deg;
        if (v->empty()) continue;
        std::vector<double> sorted = *v;
        std::sort(sorted.begin(), sorted.end());
        out = {sorted[sorted.size() / 2], sorted[std::min(sorted.size() - 1, sorted.size() * 95 / 100)], sorted.back()};
    }
    s.stage_median = {eval::median(stage_[0]), eval::median(stage_[1]), eval::median(stage_[2]),
                      eval::median(stage_[3]), eval::median(stage_[4]), s.ms_median};
    // ATE against the rawlog's own ground truth, when it has one (same frame as the output, no
    // alignment): GT interpolated at each estimate's time (gaps up to 1 s), then eval's ATE.
    const Trajectory est = trajectoryOf(est_), gt = trajectoryOf(gt_);
    Trajectory gt_at;
    for (const auto& e : est)
        if (const auto g = interpolateAt(gt, e.t, 1.0, 1e-3)) gt_at.push_back({e.t, *g, {}});
    if (!gt_at.empty()) {
        const eval::Association pairs = eval::associate(est, gt_at, 1e-6);
        const eval::AteResult ate = eval::computeAte(est, gt_at, pairs, false);
        s.gt_matched = ate.trans.n;
        if (ate.trans.n) s.ate_rmse = ate.trans.rmse, s.ate_max = ate.trans.max;
    }
}

io::Json summaryJson(const RunSummary& s) {
    const auto& m = s.stage_median;
    const auto& fa = s.flagged_axis;
    // -1 marks "no ground truth in the rawlog": null.
    const auto orNull = [](double v) { return v < 0 ? io::Json(nullptr) : io::Json(v); };
    const auto& rs = s.rawlog;
    return {{"status", s.status},
            {"error", s.error.empty() ? io::Json(nullptr) : io::Json(s.error)},
            {"method", s.method},
            {"frames", s.frames},
            {"frames_diverged", s.diverged},
            {"frames_converged", s.converged},
            {"frames_with_imu", s.used_imu},
            {"frames_with_prior", s.with_prior},
            {"frames_recovered", s.recovered},
            {"frames_health", {{"ok", s.health[0]}, {"degraded", s.health[1]}, {"lost", s.health[2]}}},
            {"frames_flagged", s.flagged},
            {"frames_flagged_without_prior", s.flagged_without_prior},
            {"frames_flagged_per_axis",
             {{"x", fa[0]},
              {"y", fa[1]},
              {"z", fa[2]},
              {"roll", fa[3]},
              {"pitch", fa[4]},
              {"yaw", fa[5]}}},
            {"ms_per_frame_median", s.ms_median},
            {"ms_per_frame_p95", s.ms_p95},
            {"ms_per_frame_mean", s.ms_mean},
            {"cpu_ms_per_frame_median", s.cpu_ms_median},
            {"fps", s.fps},
            {"stage_ms_median",
             {{"predict", m.predict},
              {"preprocess", m.preprocess},
              {"associate", m.associate},
              {"risk", m.risk},
              {"solve", m.solve},
              {"total", m.total}}},
            {"map_points", s.map_points},
            {"map_prepare_s", s.map_prepare_s},
            {"map_reloads", s.map_reloads},
            {"map_points_max", s.map_points_max},
            {"map_reload_s_max", s.map_reload_s_max},
            {"map_reload_wait_s_max", s.map_reload_wait_s_max},
            {"pose_sigma_xyz_m", {{"median", orNull(s.sigma_xyz[0])}, {"p95", orNull(s.sigma_xyz[1])}, {"max", orNull(s.sigma_xyz[2])}}},
            {"pose_sigma_deg", {{"median", orNull(s.sigma_deg[0])}, {"p95", orNull(s.sigma_deg[1])}, {"max", orNull(s.sigma_deg[2])}}},
            {"gt_frames_matched", s.gt_matched},
            {"ate_rmse_vs_rawlog_gt", orNull(s.ate_rmse)},
            {"ate_max_vs_rawlog_gt", orNull(s.ate_max)},
            {"rawlog",
             {{"scans_read", rs.lidar},
              {"scans_empty_skipped", rs.empty_scans},
              {"scans_unselected", rs.unselected_scans},
              {"invalid_points_dropped", rs.invalid_points},
              {"imu", rs.imu},
              {"imu_invalid_skipped", rs.invalid_imu},
              {"odom_alt", rs.odom_alt},
              {"gt", rs.gt},
              {"unknown_observations", rs.unknown_observations}}}};
}

void RunOutputs::finish(const RunSummary& s) {
    // Non-finite values (e.g. the ATE of a run started 1e300 m away) are written as null, each
    // with a warning.
    const io::Json summary = summaryJson(s);
    io::saveJson((std::filesystem::path(dir_) / "summary.json").string(), summary);
    PointCloud cloud;
    cloud.points = std::move(map_);  // the last use of the points: no copy of a long run's map
    map_.clear();
    io::savePointCloud((std::filesystem::path(dir_) / "localized_map.pcd").string(), cloud);
    if (report_)
        writeTextFile((std::filesystem::path(dir_) / "report.html").string(), report_->html(summary, dir_));
}

}  // namespace superloc::app
