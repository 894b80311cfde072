// One run's evaluation: every metric of doc/evaluation.md from an estimate, its GT and optionally the
// maps and the localizer's frame log; plus its JSON and Markdown forms.
#pragma once

#include <array>

#include <superloc/eval/eval_params.h>
#include <superloc/eval/frame_log.h>
#include <superloc/eval/map_metrics.h>
#include <superloc/eval/robustness.h>
#include <superloc/eval/timing.h>
#include <superloc/eval/trajectory_metrics.h>
#include <superloc/io/json_file.h>

#include <map>
#include <optional>
#include <string>

namespace superloc::eval {

/// Health (frames.csv `health`) against the ground-truth error of the same frame: counts per
/// state (ok, degraded, lost) and error bucket (< 0.1 m; 0.1-0.5 m; > 0.5 m or > 5 deg).
struct HealthConfusion {
    std::array<std::array<size_t, 3>, 3> counts{};  ///< [state][bucket]
    size_t unmatched = 0;                          ///< frames without a GT pose in tolerance
    /// Frames more than 0.5 m / 5 deg off that were reported ok: the number that must be 0.
    size_t confidentlyWrong() const { return counts[0][2]; }
};
inline constexpr const char* kHealthStates[3] = {"ok", "degraded", "lost"};
inline constexpr const char* kErrorBuckets[3] = {"< 0.1 m", "0.1-0.5 m", "> 0.5 m or > 5 deg"};

/// The confusion table of a run whose frame log has a health column (frames[i] is est[i]).
HealthConfusion healthConfusion(const Trajectory& est, const Trajectory& gt, const FrameLog& frames,
                                double assoc_tolerance);

/// Consistency of the pose covariance against ground truth (doc/evaluation.md, "Consistency"):
/// per frame that has a covariance, is not lost and has a GT pose, the normalized estimation
/// error squared NEES = e^T C^-1 e of the position (3 dof: e = t_est - t_gt in the map frame),
/// the rotation (3 dof: e = Log(R_est R_gt^T), about the map's axes with the 6 x 6 of
/// trajectory_cov.txt; about the pose's own axes with frames.csv's sigma_* alone) and the full
/// pose (6 dof, needs the 6 x 6). A consistent covariance gives an average (ANEES) near the dof
/// and 95 % of frames under the chi-square 95 % bound (7.81 for 3 dof, 12.59 for 6).
struct Consistency {
    std::vector<double> t, pos, rot, pose;  ///< per frame (pose: empty without the 6 x 6)
    double anees_pos = 0, anees_rot = 0, anees_pose = 0;
    double under95_pos = 0, under95_rot = 0, under95_pose = 0;  ///< share of frames under the bound
    bool full = false;  ///< from the 6 x 6 covariances (else rotation from the diagonal stds)
    size_t frames() const { return pos.size(); }
};
inline constexpr double kChi2_3dof_95 = 7.815;
inline constexpr double kChi2_6dof_95 = 12.592;
/// The table of a run whose frame log has the covariance columns (frames[i] is est[i]).
Consistency consistency(const Trajectory& est, const Trajectory& gt, const FrameLog& frames, double assoc_tolerance);
io::Json toJson(const Consistency& c, bool with_series);

/// Risk as a failure predictor (issue: "Risk as a measured failure predictor"): per rule of
/// frames.csv (kRuleColumns) and axis, the frames flagged against the frames that failed along
/// that axis. The error of a frame is E = T_gt^-1 T_est, in the GT pose's own axes (the
/// trajectory's frame: the LiDAR, whose axes are the body's in every data set here): it fails
/// along x, y, z when |E.translation()_k| > risk_fail_xyz, along roll, pitch, yaw when the
/// component k of E's rotation vector exceeds risk_fail_deg.
struct RiskPrediction {
    struct Counts {
        size_t tp = 0, fp = 0, fn = 0, tn = 0;  ///< flagged & failed, flagged & fine, ...
        /// tp / (tp + fp) and tp / (tp + fn); NaN when the denominator is 0.
        double precision() const;
        double recall() const;
        Counts& operator+=(const Counts& o);
    };
    std::array<std::array<Counts, 6>, kRules> counts{};  ///< [rule][axis] (kRuleColumns)
    size_t frames = 0;                             ///< frames matched to GT
    RiskPrediction& operator+=(const RiskPrediction& o);
};

/// The table of a run whose frame log has the rule columns (frames[i] is est[i]).
RiskPrediction riskPrediction(const Trajectory& est, const Trajectory& gt, const FrameLog& frames,
                              const EvalParams& params);

/// The table as Markdown: one row per rule, precision / recall per axis ("–" when undefined).
std::string riskPredictionMarkdown(const RiskPrediction& p);
io::Json toJson(const RiskPrediction& p);

struct EvalResult {
    size_t est_frames = 0, gt_frames = 0, matched_frames = 0;
    bool aligned = false;
    AteResult ate;
    RpeResult rpe;
    RobustnessCurve rp, rr;                          ///< Rp (translation, m) and Rr (rotation, rad)
    std::optional<MapResult> map;                    ///< when both maps were given
    std::optional<TimingStats> timing;               ///< ms_total of the frame log
    std::map<std::string, TimingStats> stages;       ///< every ms_* column of the frame log
    std::optional<double> degenerate_frame_percent;  ///< [%] frames with any axis flagged
    std::optional<HealthConfusion> health;           ///< when the frame log has a health column
    std::optional<RiskPrediction> risk;              ///< when the frame log has the rule columns
    std::optional<Consistency> consistency;          ///< when the frame log has the covariance columns
};

/// Evaluates one run. `est_map`/`gt_map` and `frames` may be null.
EvalResult evaluate(const Trajectory& est, const Trajectory& gt, const EvalParams& params,
                    const PointCloud* est_map = nullptr, const PointCloud* gt_map = nullptr,
                    const FrameLog* frames = nullptr);

/// The result as one JSON object (F1 curves included when `with_curves`); non-finite numbers
/// stay as they are (io::toJsonText / io::saveJson turn them into null).
io::Json toJson(const EvalResult& r, bool with_curves = true);

/// A human-readable Markdown summary (a two-column metric table).
std::string summaryMarkdown(const EvalResult& r);

}  // namespace superloc::eval
