// ATE and RPE (doc/evaluation.md) on timestamp-associated trajectories.
#include <superloc/core/se3.h>
#include <superloc/eval/trajectory_metrics.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace superloc::eval {

Association associate(const Trajectory& est, const Trajectory& gt, double tolerance) {
    Association a;
    a.gt_of_est.assign(est.size(), SIZE_MAX);
    std::vector<size_t> owner(gt.size(), SIZE_MAX);  // estimate holding each GT frame
    std::vector<double> owner_dt(gt.size(), 0);
    for (size_t i = 0; i < est.size(); ++i) {
        // Nearest GT time: the first GT at or after t_est, or the one before it.
        const auto it = std::lower_bound(gt.begin(), gt.end(), est[i].t,
                                         [](const PoseStamped& g, double t) { return g.t < t; });
        size_t best = SIZE_MAX;
        double best_dt = std::numeric_limits<double>::infinity();
        for (const auto cand : {it, it == gt.begin() ? gt.end() : std::prev(it)}) {
            if (cand == gt.end()) continue;
            const double dt = std::abs(cand->t - est[i].t);
            if (dt < best_dt) best_dt = dt, best = static_cast<size_t>(cand - gt.begin());
        }
        if (best == SIZE_MAX || best_dt > tolerance) continue;
        if (owner[best] != SIZE_MAX && owner_dt[best] <= best_dt) continue;
        if (owner[best] != SIZE_MAX) a.gt_of_est[owner[best]] = SIZE_MAX;
        owner[best] = i;
        owner_dt[best] = best_dt;
        a.gt_of_est[i] = best;
    }
    for (size_t i = 0; i < est.size(); ++i)
        if (a.gt_of_est[i] != SIZE_MAX) a.pairs.emplace_back(i, a.gt_of_est[i]);
    return a;
}

ErrorStats errorStats(std::vector<double> v) {
    ErrorStats s;
    s.n = v.size();
    if (v.empty()) return s;
    double sum = 0, sq = 0;
    for (double e : v) sum += e, sq += e * e, s.max = std::max(s.max, e);
    s.mean = sum / v.size();
    s.rmse = std::sqrt(sq / v.size());
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    s.median = v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
    return s;
}

SE3d alignSE3(const Trajectory& est, const Trajectory& gt, const Association& a) {
    if (a.pairs.size() < 3) return SE3d::Identity();
    Eigen::Matrix3Xd src(3, a.pairs.size()), dst(3, a.pairs.size());
    for (size_t k = 0; k < a.pairs.size(); ++k) {
        src.col(k) = est[a.pairs[k].first].pose.translation();
        dst.col(k) = gt[a.pairs[k].second].pose.translation();
    }
    // Umeyama (1991): least-squares rigid transform, without scale.
    SE3d T;
    T.matrix() = Eigen::umeyama(src, dst, false);
    if (!T.matrix().allFinite()) return SE3d::Identity();  // degenerate (collinear) input
    return T;
}

AteResult computeAte(const Trajectory& est, const Trajectory& gt, const Association& a,
                     bool align) {
    AteResult r;
    if (align) r.T_gt_est = alignSE3(est, gt, a);
    std::vector<double> rot;
    for (const auto& [i, j] : a.pairs) {
        const SE3d P = r.T_gt_est * est[i].pose;
        r.trans_errors.push_back(translationDistance(gt[j].pose, P));
        rot.push_back(rotationAngle(gt[j].pose, P));
    }
    r.trans = errorStats(r.trans_errors);
    r.rot = errorStats(rot);
    return r;
}

RpeResult computeRpe(const Trajectory& est, const Trajectory& gt, const Association& a) {
    RpeResult r;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> t_ok, r_ok;
    for (size_t i = 1; i < est.size(); ++i) {
        const size_t g0 = a.gt_of_est[i - 1], g1 = a.gt_of_est[i];
        if (g0 == SIZE_MAX || g1 == SIZE_MAX) {
            r.frame_trans.push_back(nan);
            r.frame_rot.push_back(nan);
            continue;
        }
        const SE3d dG = gt[g0].pose.inverse() * gt[g1].pose;
        const SE3d dP = est[i - 1].pose.inverse() * est[i].pose;
        const SE3d E = dG.inverse() * dP;
        r.frame_trans.push_back(E.translation().norm());
        r.frame_rot.push_back(logSO3(E.linear()).norm());
        t_ok.push_back(r.frame_trans.back());
        r_ok.push_back(r.frame_rot.back());
    }
    r.trans = errorStats(t_ok);
    r.rot = errorStats(r_ok);
    return r;
}

}  // namespace superloc::eval
