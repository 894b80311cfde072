// Recovery of a diverged constant-velocity frame (no IMU; doc/localizer.md step 7): the solve is
// retried from yaw hypotheses around the prediction and around the previous pose.
#include <superloc/core/se3.h>
#include <superloc/localization/localizer.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace superloc::localization {
namespace {
constexpr double kDeg = M_PI / 180.0;
}  // namespace

bool Localizer::recoverFromYawHypotheses(const Scan& scan, const Prediction& pred, const FrameReport& base,
                                         FrameReport& rep) {
    // Without IMU a fast turn between two sweeps leaves the constant-velocity prediction tens of
    // degrees off, beyond what scan-to-map ICP converges from. Try yaw offsets (about the map's
    // vertical) around the prediction and around the previous pose (the motion may have stopped
    // or reversed): a short wide search from each, then the most inliers is refined. It replaces
    // the frame's solution only when it has more inliers and passes the divergence checks.
    const auto& lp = params_.loc;
    const fusion::FrameState start_state = cur_;
    // What the attempts overwrite, to put back when none of them wins.
    const auto saved_corr = corr_;
    const auto saved_stats = last_stats_;
    const SE3d saved_T_map_lidar = last_T_map_lidar_;
    std::vector<SE3d> starts;
    for (const SE3d& c : {pred.T_map_imu, prev_.T_map_imu()}) {
        for (double a = 0; a <= lp.recovery_max_yaw_deg + 1e-9; a += lp.recovery_yaw_step_deg) {
            for (double sgn : {1.0, -1.0}) {
                if (a == 0 && sgn < 0) continue;
                SE3d T = c;
                T.linear() = Eigen::AngleAxisd(sgn * a * kDeg, Vec3d::UnitZ()).toRotationMatrix() * c.linear();
                starts.push_back(T);
            }
        }
    }
    // One hypothesis: solve from `start` (rounds = 0: the full wide search) and check it.
    // finish() runs as on a first frame: no jump check, a recovered pose is far from the
    // prediction by construction; the inlier check decides.
    const auto attempt = [&](const SE3d& start, int rounds) {
        cur_ = start_state;
        cur_.setPose(start);
        FrameReport r = base;
        solveIcp(nullptr, true, r, rounds);
        Prediction p = pred;
        p.T_map_imu = start;
        finish(scan, p, true, r);
        return r;
    };
    // Screen every hypothesis with a few rounds, then run the full wide search from the
    // kRefine best (the right start may still trail after the screening rounds: campus-ouster
    // frame 14 is at 0.26 after 8 rounds, 0.88 after the full search).
    constexpr size_t kRefine = 4;
    std::vector<std::pair<double, size_t>> screened;
    for (size_t i = 0; i < starts.size(); ++i)
        screened.emplace_back(attempt(starts[i], lp.recovery_rounds).inlier_ratio, i);
    const size_t n_refine = std::min(kRefine, screened.size());
    std::partial_sort(screened.begin(), screened.begin() + static_cast<std::ptrdiff_t>(n_refine), screened.end(),
                      [](const auto& a, const auto& b) { return a.first > b.first; });
    size_t best = screened.front().second;
    double best_ratio = -1;
    for (size_t k = 0; k < n_refine; ++k) {
        const FrameReport r = attempt(starts[screened[k].second], 0);
        if (!r.diverged && r.inlier_ratio > best_ratio) best_ratio = r.inlier_ratio, best = screened[k].second;
    }
    FrameReport r = attempt(starts[best], 0);  // again, so that every buffer belongs to the winner
    const bool ok = !r.diverged && (rep.diverged || r.inlier_ratio > rep.inlier_ratio);
    if (ok) {
        r.recovered = true;
        r.ms = rep.ms;
        rep = r;
    } else {
        corr_ = saved_corr;
        last_stats_ = saved_stats;
        last_T_map_lidar_ = saved_T_map_lidar;
    }
    return ok;
}

}  // namespace superloc::localization
