// Recovery of a diverged constant-velocity frame (no IMU; doc/localizer.md step 7): the solve is
// retried from yaw hypotheses around the prediction and around the previous pose.
#include <superloc/core/se3.h>
#include <superloc/localization/localizer.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

namespace superloc::localization {
namespace {
constexpr double kDeg = M_PI / 180.0;
}  // namespace

bool Localizer::recoverFromYawHypotheses(const Scan& scan, const Prediction& pred, const FrameReport& base,
                                         const fusion::FrameState& start, FrameReport& rep) {
    // Without IMU a fast turn between two sweeps leaves the constant-velocity prediction tens of
    // degrees off, beyond what scan-to-map ICP converges from. Try yaw offsets (about the map's
    // vertical) around the prediction and around the previous pose (the motion may have stopped
    // or reversed): a short wide search from each, then the most inliers is refined. It replaces
    // the frame's solution only when it has more inliers and passes the divergence checks.
    const auto& lp = params_.loc;
    // Everything a solve leaves behind (state, report, the buffers the app reads afterwards).
    struct Outcome {
        FrameReport rep;
        fusion::FrameState state;
        std::vector<fusion::ScanCorrespondence> corr;
        AssociationStats stats;
        SE3d T_map_lidar;
    };
    const auto capture = [this](const FrameReport& r) {
        return Outcome{r, cur_, corr_, last_stats_, last_T_map_lidar_};
    };
    const Outcome solved = capture(rep);

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
    // One hypothesis: solve from `T_start` (rounds = 0: the full wide search) and check it.
    // finish() runs as on a first frame: no jump check, a recovered pose is far from the
    // prediction by construction; the inlier check decides.
    const auto attempt = [&](const SE3d& T_start, int rounds) {
        cur_ = start;
        cur_.setPose(T_start);
        FrameReport r = base;
        solveIcp(nullptr, true, r, rounds);
        Prediction p = pred;
        p.T_map_imu = T_start;
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
    std::optional<Outcome> best;
    for (size_t k = 0; k < n_refine; ++k) {
        const FrameReport r = attempt(starts[screened[k].second], 0);
        if (!r.diverged && (!best || r.inlier_ratio > best->rep.inlier_ratio)) best = capture(r);
    }
    const bool ok = best && (solved.rep.diverged || best->rep.inlier_ratio > solved.rep.inlier_ratio);
    const Outcome& keep = ok ? *best : solved;
    cur_ = keep.state;
    corr_ = keep.corr;
    last_stats_ = keep.stats;
    last_T_map_lidar_ = keep.T_map_lidar;
    rep = keep.rep;
    rep.ms = solved.rep.ms;
    rep.recovered = ok;
    return ok;
}

}  // namespace superloc::localization
