// A frame whose velocity is unknown (doc/localizer.md, "Unknown velocity"): without IMU, its
// motion measured against the last scan; with timed points, its sweep's velocity estimated with
// its pose.
#include <superloc/core/se3.h>
#include <superloc/core/timing.h>
#include <superloc/features/deskew.h>
#include <superloc/fusion/scan_factor.h>
#include <superloc/localization/tracker.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

namespace superloc::localization {

namespace {
using Clock = SteadyClock;

/// The turn about the map's vertical through the sensor (at T, the pose of no motion) under which
/// most of `pts` (body frame, every stride-th) have a point of `scan_map` within 1 m, among the
/// turns in steps of `step_deg`; no turn unless one scores a fifth more than none. A 2 s gap on
/// foot turns the scan by up to 100 deg (campus-ouster's odd scans), beyond ICP's basin from no
/// motion; the translation of such a gap (a metre or two) is left to the registration.
double firstGuessYaw(const std::vector<Vec3d>& pts, const SE3d& T, const map::PriorMap& scan_map, double step_deg) {
    if (!(step_deg > 0) || pts.empty() || scan_map.size() == 0) return 0.0;
    constexpr float kNear = 1.0f;  // [m]
    const size_t stride = std::max<size_t>(1, pts.size() / 256);
    const auto score = [&](double yaw) {
        const SE3d Ty = turnedAboutVertical(T, yaw);
        int n = 0;
        for (size_t i = 0; i < pts.size(); i += stride) {
            const Vec3d x = Ty * pts[i];
            n += scan_map.nearest(x.cast<float>()).second <= kNear * kNear;
        }
        return n;
    };
    const int none = score(0.0);
    int best = none;
    double best_yaw = 0.0;
    const int steps = static_cast<int>(std::floor(180.0 / step_deg + 1e-9));
    for (int k = 1; k <= steps; ++k)
        for (const int sign : {1, -1}) {
            if (sign < 0 && k * step_deg >= 180.0 - 1e-9) continue;  // +180 and -180 are one turn
            const double yaw = sign * k * step_deg * kDeg;
            const int s = score(yaw);
            if (s > best) best = s, best_yaw = yaw;
        }
    return 5 * best > 6 * none ? best_yaw : 0.0;
}

}  // namespace

bool Tracker::measureMotion(Frame& f) {
    // The last scan as a small map: its voxel candidates are one point per features.voxel_size
    // voxel already, so the map keeps them all; normals face the LiDAR that saw them.
    map::MapParams mp;
    mp.voxel_size = 0;
    mp.geometry_at_load = false;  // one frame's use: only the points its features meet
    PointCloud cloud;  // the points are used once: the frame keeps its own scan when it ends
    cloud.points = std::move(last_scan_points_);
    last_scan_points_.clear();
    const map::PriorMap scan_map(cloud, mp, last_scan_origin_);
    FrameSolution sol;
    sol.state = f.start;
    // No motion since the last scan, or a turn about the vertical where one fits it clearly better.
    const double yaw = firstGuessYaw(f.features.pts_body, f.prev.T_map_imu(), scan_map, params_.loc.last_scan_yaw_step);
    sol.state.setPose(turnedAboutVertical(f.prev.T_map_imu(), yaw));
    RegistrationProblem p = problem(f, SolvePurpose::LastScan, true, nullptr);
    p.map = &scan_map;
    // Every k-th feature (LocalizationParams::last_scan_features): the motion only has to land
    // the map solve inside its basin, and that solve uses them all (campus-ouster's odd scans:
    // the registration took 19 of a frame's 22 ms with all 2 000).
    const ScanFeatures sub = strided(f.features, params_.loc.last_scan_features);
    if (!sub.pts_body.empty()) p.features = &sub;
    icp_.solve(p, sol);
    const TrackReport& r = sol.report;
    const InlierStats in = inlierStats(sol.corr, p.features->pts_body.size(), sol.state.T_map_imu(),
                                       params_.loc.inlier_dist);
    f.report.ms.associate += r.ms.associate;
    f.report.ms.solve += r.ms.solve;
    // Not "converged" as a criterion: the last scan's 0.5 m candidates leave the last
    // millimetres hesitant; a wrong motion is caught by the map solve's jump check.
    if (r.diverged || in.ratio < params_.loc.min_inlier_ratio) return false;
    f.pred.T_map_imu = sol.state.T_map_imu();
    return true;
}

void Tracker::sweepVelocity(Frame& f, const Prediction& pred, const imu::Preintegration* imu, FrameSolution& sol) {
    TrackReport& rep = sol.report;
    const Scan& scan = *f.scan;
    ScanFeatures& ft = f.features;
    if (scan.rel_time.size() != scan.size() || ft.feature_idx.empty()) return;
    const float s_min = *std::min_element(scan.rel_time.begin(), scan.rel_time.end());
    if (!(s_min < 0)) return;
    const Mat3d R_il = scan.T_imu_lidar.linear();
    const Vec3d w_l = pred.twist_from_imu ? Vec3d(R_il.transpose() * pred.w_body) : Vec3d::Zero();
    // A prior on the velocity (1 m/s around zero) keeps the step defined where the scene cannot
    // tell it (along a corridor; vertically, where it looks like roll and pitch); thousands of
    // correspondences outweigh it wherever the scene does tell it.
    constexpr double kVelocityPriorSigma = 1.0, kSettled = 0.02;  // [m/s]
    constexpr int kSteps = 4;
    const fusion::RobustKernel kernel = fusion::robustKernelFromString(params_.fusion.robust_kernel);
    Vec3d v_l = Vec3d::Zero();
    std::vector<uint32_t> feature_of;
    const double inv_var = 1.0 / (params_.fusion.scan_sigma * params_.fusion.scan_sigma);
    int rounds = rep.rounds, iterations = rep.iterations;
    for (int step = 0; step < kSteps && !rep.diverged; ++step) {
        // The world point of feature f moves by R R_il s_f dv when the sweep velocity (LiDAR
        // frame) changes by dv: three more columns beside the pose's six.
        const SE3d T = sol.state.T_map_imu();
        const Mat3d R = T.linear();
        auto t0 = Clock::now();
        associate(ft.pts_body, T, *map_, icp_.association(), sol.corr, sol.stats, &feature_of);
        rep.ms.associate += msSince(t0);
        Eigen::Matrix<double, 9, 9> H = Eigen::Matrix<double, 9, 9>::Zero();
        Eigen::Matrix<double, 9, 1> g = Eigen::Matrix<double, 9, 1>::Zero();
        double r[3], J[18];
        Eigen::Matrix<double, 3, 9> J9;  // the first residualDim rows are used
        for (size_t k = 0; k < sol.corr.size(); ++k) {
            const Correspondence& c = sol.corr[k];
            if (c.weight <= 0) continue;
            const double s = scan.rel_time[ft.feature_idx[feature_of[k]]];
            fusion::correspondenceResidual(c, R, T.translation(), r, J);
            const int dim = fusion::residualDim(c.type);
            const Eigen::Map<const Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J6(J);
            const Eigen::Map<const Vec3d> res3(r);
            const auto res = res3.head(dim);
            const double w = c.weight * fusion::robustWeight(kernel, res.norm(), params_.fusion.kernel_scale) * inv_var;
            J9.topLeftCorner(dim, 6) = J6.topRows(dim);
            J9.topRightCorner(dim, 3) = J6.topLeftCorner(dim, 3) * R * R_il * s;
            H.noalias() += w * J9.topRows(dim).transpose() * J9.topRows(dim);
            g.noalias() += w * J9.topRows(dim).transpose() * res;
        }
        H.bottomRightCorner<3, 3>() += Mat3d::Identity() / (kVelocityPriorSigma * kVelocityPriorSigma);
        g.tail<3>() += v_l / (kVelocityPriorSigma * kVelocityPriorSigma);
        const Eigen::Matrix<double, 9, 1> delta = -H.ldlt().solve(g);
        if (!delta.allFinite()) break;
        const Vec3d dv = delta.tail<3>();
        v_l += dv;
        // Deskew again with the estimate and re-solve from the current pose.
        t0 = Clock::now();
        ft.redeskew(scan, features::SweepMotion::fromTwist(v_l, w_l, -s_min));
        rep.ms.preprocess += msSince(t0);
        rep.deskewed = true;
        rep.rounds = 0, rep.iterations = 0;
        trackedSolve(icp_, f, sol, /*wide=*/false, imu);
        rounds += rep.rounds, iterations += rep.iterations;
        if (dv.norm() < kSettled) break;
    }
    rep.rounds = rounds, rep.iterations = iterations;
    rep.sweep_velocity = v_l;
}

}  // namespace superloc::localization
