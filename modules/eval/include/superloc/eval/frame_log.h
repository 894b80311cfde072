// The localizer's per-frame log (`frames.csv`, doc/localizer.md), as the evaluation needs it.
#pragma once

#include <superloc/core/types.h>

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace superloc::eval {

struct FrameRecord {
    double t = 0;                      ///< [s]
    Vec6d gamma = Vec6d::Zero();       ///< confidence, (x y z roll pitch yaw)
    std::array<bool, 6> degenerate{};  ///< parsed from the `degenerate` letters
    double ms_total = 0;               ///< [ms] wall time of the frame
    std::string health;                ///< "ok" | "degraded" | "lost"; empty when the log has none
    /// The flags_labels1, flags_labels2, flags_eigen columns (risk::RiskReport::RuleFlags) and
    /// `degenerate` (the estimate's weak directions, the decision), in kRuleColumns order.
    std::array<std::array<bool, 6>, 4> rule_flags{};
    /// The pose's covariance: the position block in the map frame [m^2] (cov_xx ... cov_zz) and
    /// the rotation's std about the pose's own axes [deg] (sigma_roll ... sigma_yaw); the full
    /// 6 x 6 (ROS convention) from trajectory_cov.txt beside frames.csv when it is there.
    std::optional<Mat3d> cov_pos;
    std::optional<Vec3d> sigma_rot_deg;
    std::optional<Mat6d> cov6;
};

/// The failure-prediction rules of frames.csv, in FrameRecord::rule_flags order: their column
/// names and short names.
inline constexpr int kRules = 4;
inline constexpr const char* kRuleColumns[kRules] = {"flags_labels1", "flags_labels2", "flags_eigen", "degenerate"};
inline constexpr const char* kRuleNames[kRules] = {"γ, 1 rotation label", "γ, 2 rotation labels",
                                              "Hessian eigenvalues", "estimate (scan + IMU) weak"};

struct FrameLog {
    std::vector<FrameRecord> frames;
    /// Every `ms_*` column (ms_total included) [ms]; a row with more or fewer cells than the
    /// header adds only to ms_total.
    std::map<std::string, std::vector<double>> stage_ms;
    bool has_gamma = false;  ///< the file had the six gamma_* columns
    bool has_health = false;  ///< the file had the `health` column
    bool has_rules = false;   ///< the file had the flags_* columns and `degenerate`
    bool has_cov = false;     ///< the file had the cov_* and sigma_* columns
    bool has_cov6 = false;    ///< trajectory_cov.txt beside it gave every frame its 6 x 6
};

/// Parses the `degenerate` column ("x", "xyaw", "rollpitch", "" ...) into flags; throws
/// std::invalid_argument on an unknown letter sequence.
std::array<bool, 6> parseDegenerateAxes(const std::string& letters);

/// Reads frames.csv: a header row naming the columns, then one row per frame. Required: `t` and
/// `ms_total`; gamma_*, `degenerate` and the covariance columns are used when present, and
/// trajectory_cov.txt in the same folder (one line per frame, t then 36 numbers) when its times
/// are the frames'. Throws std::runtime_error
/// "FILE:LINE: ..." on a missing file or column, or a malformed number.
FrameLog loadFrameLog(const std::string& path);

}  // namespace superloc::eval
