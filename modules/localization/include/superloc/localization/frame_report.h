// What the Localizer reports for every scan (doc/localizer.md, Outputs). "Diverged" and "not converged"
// are fields, never exceptions.
#pragma once

#include <superloc/core/types.h>
#include <superloc/imu/preintegration.h>
#include <superloc/localization/health.h>
#include <superloc/localization/relocalization.h>
#include <superloc/risk/alignment_risk.h>

#include <array>
#include <string>

namespace superloc::localization {

/// Wall time per pipeline stage [ms].
struct StageTimes {
    double predict = 0;     ///< IMU preintegration / constant-velocity prediction
    double preprocess = 0;  ///< range filter, voxel selection, feature cap, deskew
    double associate = 0;   ///< all association rounds (kd-tree queries, classification)
    double risk = 0;        ///< alignment risk of the first association, the estimate's information, the pose's covariance
    double solve = 0;       ///< Ceres solves (or the NDT registration)
    double total = 0;       ///< whole process() call
    double total_cpu = 0;   ///< CPU time of this thread in process() (robust to a busy machine)
};

/// What a frame's own steps give (doc/localizer.md "One frame"), as values: the prediction and
/// the features (steps 1-2: Tracker::begin, Frame::report), then every solve's registration,
/// fusion, quality and covariance (steps 3-6: FrameSolution::report, each solve its own copy,
/// started from the frame's). The Localizer's FrameReport is this plus what health and the
/// Recovery add.
struct TrackReport {
    SE3d T_map_lidar = SE3d::Identity();
    SE3d T_map_imu = SE3d::Identity();
    SE3d T_map_lidar_pred = SE3d::Identity();  ///< the prediction the frame started from
    Vec3d velocity = Vec3d::Zero();    ///< [m/s] body velocity in map
    imu::ImuBias bias;

    // Alignment risk at the predicted pose (doc/method.md §1): x y z roll pitch yaw.
    Vec6d gamma = Vec6d::Zero();
    /// The weak axes: of the estimate without odom_alt (fusion::weakness) on a tracked frame,
    /// where superloc fuses odom_alt; of the scan's gamma (as flags_labels2) on other solves.
    std::array<bool, 6> degenerate{};
    std::string degenerate_axes;       ///< flagged axes as letters ("x", "xyaw", "")
    /// The three failure-prediction rules of risk::RiskReport::RuleFlags, as letters.
    std::string flags_labels1, flags_labels2, flags_eigen;
    // The classic analysis of the same correspondences, for comparison (not used by superloc):
    // eigenvalues of H = sum w J J^T divided by sum w (ascending), and of its translation block
    // with the weakest translation direction in body axes (risk::RiskReport).
    Vec6d hessian_eigenvalues = Vec6d::Zero();
    Vec3d translation_eigenvalues = Vec3d::Zero();
    Vec3d weakest_translation = Vec3d::Zero();
    /// What the estimate knows of each axis without odom_alt, at the predicted pose before the
    /// solve (doc/method.md §2, body axes): the scan's information counted by its labels
    /// [1/m^2, 1/rad^2], the std it alone gives, the std of scan + IMU window (+inf where
    /// nothing holds the axis; 0: not computed). Where it is weak is `degenerate` (below).
    Vec6d scan_info = Vec6d::Zero();
    Vec6d scan_sigma = Vec6d::Zero();
    Vec6d est_sigma = Vec6d::Zero();
    /// The pose's covariance (fusion::PosePosterior, doc/method.md §4): of a right perturbation
    /// T_map_imu Exp(d), d = (translation in body axes [m], rotation vector [rad]); zero when the
    /// frame has none (outputs turn it into the reported pose's ROS convention: toReported).
    Mat6d cov = Mat6d::Zero();
    /// The axes the scan constrains weakly (gamma below [health] weak_gamma), as letters: held
    /// by the IMU or odom_alt, reported, not degraded by themselves.
    std::string weak_axes;
    /// [s] how long a translation axis has been weak in the scan (gamma below [health]
    /// weak_gamma) without odom_alt holding it (its per-frame std along it above [health]
    /// max_sigma_xyz / 10): carried by the prediction alone (0: not now)
    double dead_reckoning_s = 0;
    bool prior_used = false;           ///< a relative-pose prior entered the solve
    Vec6d prior_weight = Vec6d::Zero();  ///< diagonal information of that prior

    // Counts
    size_t points_raw = 0;        ///< points in the scan
    size_t points_valid = 0;      ///< after NaN/range filter
    size_t candidates = 0;        ///< after voxel selection
    size_t features = 0;          ///< used for association (capped)
    size_t corr_plane = 0, corr_line = 0, corr_point = 0;  ///< last association, by type
    size_t too_far = 0;           ///< features without a map point in range (last association)

    // Quality
    double inlier_ratio = 0;      ///< features with residual < inlier_dist at the final pose
    double residual_rms = 0;      ///< [m] RMS residual of those inliers
    int rounds = 0;               ///< association rounds run
    int iterations = 0;           ///< solver iterations over all rounds
    int final_level = 0;          ///< voxel map level of the last round (0 = finest)
    bool coarse_start = false;    ///< velocity unknown: solved from the coarsest level, no jump check
    /// velocity unknown, no IMU: the prediction is the motion measured against the last scan
    /// (LocalizationParams::motion_from_last_scan), and the frame was solved as a tracked one
    bool motion_from_scan = false;
    /// velocity unknown, timed points: the sweep's translation velocity estimated with the pose
    /// [m/s, LiDAR frame] (LocalizationParams::sweep_velocity); zero when not estimated
    Vec3d sweep_velocity = Vec3d::Zero();
    bool converged = false;       ///< last round's update below the thresholds
    double last_step_xyz = 0;     ///< [m] the last round's update (translation)
    double last_step_deg = 0;     ///< [deg] the last round's update (rotation)
    bool diverged = false;        ///< divergence detected (see reason)
    Divergence diverged_reason = Divergence::None;  ///< why (None when not diverged)
    bool used_imu = false;        ///< prediction and factor from IMU preintegration
    bool deskewed = false;

    StageTimes ms;

    /// Copies the risk step's per-frame results (gamma, flags, eigen diagnostics).
    void setRisk(const risk::RiskReport& r);
};

/// The frame's report (frames.csv, doc/localizer.md "Outputs"): assembled once per frame by
/// Localizer::process, and only there, from the values the others return: the Tracker's
/// TrackReport, the Recovery's decisions (a verified pose's TrackReport, what its search did) and
/// the health checks' Verdict.
struct FrameReport : TrackReport {
    size_t index = 0;
    double t = 0;                 ///< [s] scan time (end of sweep)
    bool recovered = false;       ///< lost or in doubt, replaced by a verified relocalization

    // Health (health.h, doc/health.md): no ground truth involved.
    Health health = Health::Ok;
    std::string health_reason;    ///< checks that failed, '+'-joined ("not_converged+weak_x")
    HealthChecks checks;          ///< the same as flags
    double inlier_reference = 0;  ///< the run's reference inlier ratio before this frame (0: none yet)
    double pred_dxyz = 0;         ///< [m] solved vs predicted LiDAR position
    double pred_ddeg = 0;         ///< [deg] solved vs predicted LiDAR rotation
    /// [deg] over the last [health] drift_window seconds of IMU-predicted frames: the solved
    /// rotation against the one the gyro alone carries from the window's first frame (0: no window)
    double imu_drift_deg = 0;
    RelocReport reloc;            ///< the relocalization run on this frame, if any

    FrameReport() = default;
    /// Frame `index` at scan time `t` with what its own steps gave.
    FrameReport(size_t index_, double t_, const TrackReport& track) : TrackReport(track), index(index_), t(t_) {}
    /// The part the Tracker's steps give.
    const TrackReport& track() const { return *this; }
    /// A solve's result replaces the frame's own (a pose the Recovery verified).
    void setTrack(const TrackReport& r) { static_cast<TrackReport&>(*this) = r; }
    /// pred_dxyz, pred_ddeg: the reported pose against the prediction it started from.
    void measurePrediction();
    /// The health checks' verdict on the frame (health, health_reason, checks, inlier_reference).
    void setVerdict(const Verdict& v) {
        health = v.health;
        health_reason = v.reason;
        checks = v.checks;
        inlier_reference = v.inlier_reference;
    }
};

}  // namespace superloc::localization
