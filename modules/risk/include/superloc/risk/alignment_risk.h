// Alignment risk (doc/method.md §1; paper §III-A "Predicting Alignment Risk", §III-B "Observability
// Estimation"): from the correspondences of one scan at its *predicted* pose, before solving,
// how well each motion direction x, y, z, roll, pitch, yaw is constrained.
//
// A pure function of the correspondences. The axes of the result are the axes the caller
// expresses p and n in (the localizer uses body axes, those of its relative-pose prior).
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/core/correspondence.h>
#include <superloc/core/types.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace superloc::risk {

/// Section [risk] of the INI.
struct RiskParams : public mrpt::config::CLoadableOptions {
    double degenerate_threshold = 0.2;  ///< [-] gamma_k below this flags axis k (paper: 0.2)
    bool weighted_labels = true;  ///< a label counts its correspondence's weight (else counts 1)
    /// Rotation labels per correspondence: 1 = the axis of largest |(p x n) . e_k| (paper
    /// Table I read literally); 2 = the two largest non-zero ones (the authors' released code):
    /// the two rotation axes the correspondence's surface can constrain. See doc/method.md.
    int rotation_labels = 2;
    /// The estimate is weak along a direction when its std there without odom_alt (the scan's
    /// information above its noise floor plus the IMU window, fusion::EstimateInformation)
    /// exceeds this: the flags `weak` of frames.csv and superloc's decision where to fuse
    /// odom_alt (doc/method.md §2)
    double weak_sigma_xyz = 0.05;  ///< [m]
    double weak_sigma_deg = 0.5;   ///< [deg]
    /// [deg] angular noise of the map's plane normals: a direction gets from the scan only the
    /// information above what normals this noisy give it by chance (a share sin^2 of this of
    /// each group's information; the small x components of a corridor's wall normals hold nothing)
    double normal_noise_deg = 4.0;
    bool keep_jacobians = false;  ///< fill RiskReport::jacobians (costs memory; off in the loop)
    bool hessian_eigen = true;    ///< compute the classic Hessian eigen-analysis for comparison

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    /// Throws ConfigError naming [risk] and the key when a value is out of range.
    void validate() const;
};

/// Label value for "no label" (skipped correspondence, or zero lever arm for rotation).
inline constexpr int8_t kNoLabel = -1;

/// Everything the risk step predicts for one scan. 6-vectors are in (x y z roll pitch yaw) order.
struct RiskReport {
    /// J_i = [n_i ; p_i x n_i] (translation first, our order; the paper writes [p x n ; n]),
    /// one per input correspondence; empty unless RiskParams::keep_jacobians.
    std::vector<Vec6d> jacobians;
    /// Per input correspondence: translation label 0 (x), 1 (y), 2 (z) and rotation label
    /// 3 (roll), 4 (pitch), 5 (yaw) — indices into the 6-vectors —, or kNoLabel.
    std::vector<int8_t> translation_label;
    std::vector<int8_t> rotation_label;
    /// Second rotation label (3..5) when rotation_labels = 2 and that torque component is
    /// non-zero, else kNoLabel.
    std::vector<int8_t> rotation_label2;
    /// N_x .. N_yaw: number of labels per axis (sum of weights when weighted_labels).
    Vec6d counts = Vec6d::Zero();
    std::array<size_t, 3> used_by_type{};  ///< used correspondences by FeatureType
    size_t skipped = 0;                    ///< non-finite, zero normal or weight <= 0
    /// Confidence gamma_k = min(1, 3 N_k / (N_x + N_y + N_z)), likewise for rotation; 0 for an
    /// empty group. Sigma_cov = diag(gamma).
    Vec6d gamma = Vec6d::Zero();
    std::array<bool, 6> degenerate{};  ///< gamma_k < degenerate_threshold

    /// Classic analysis (not used for the decision): H = sum w_i J_i J_i^T, eigenvalues
    /// ascending with unit eigenvectors as columns; condition = lambda_max / lambda_min
    /// (infinity when lambda_min <= 0). Zero when hessian_eigen is off.
    Mat6d hessian = Mat6d::Zero();
    Vec6d eigenvalues = Vec6d::Zero();
    Mat6d eigenvectors = Mat6d::Zero();
    double condition_number = 0;
    /// Sum of the weights of the used correspondences (the scale of `hessian`).
    double weight_sum = 0;
    /// Translational information per unit weight, T = sum w_i n_i n_i^T / sum w_i (trace 1,
    /// dimensionless, rotation-invariant unlike the labels): eigenvalues ascending, and the
    /// unit eigenvector of the smallest one (the weakest translation direction, in the input
    /// axes, sign chosen so that its largest component is positive). A uniform spread gives
    /// 1/3 each; a direction no correspondence constrains gives 0. Zero when hessian_eigen is off
    /// or nothing was used.
    Vec3d translation_eigenvalues = Vec3d::Zero();
    Vec3d weakest_translation = Vec3d::Zero();

    /// The failure-prediction rules compared in doc/results.md ("Risk as a failure
    /// predictor"), each a flag per axis from the same correspondences, whatever
    /// rotation_labels selects for `gamma`/`degenerate`:
    /// - labels1, labels2: gamma_k < degenerate_threshold with one or two rotation labels per
    ///   correspondence (translation flags are the same in both);
    /// - eigen: the classic Hessian-eigenvalue rule, per group so that metres and radians do
    ///   not mix: the translation block sum w n n^T and the rotation block
    ///   sum w (p x n)(p x n)^T, each divided by its trace; the eigen-directions whose eigenvalue
    ///   is below degenerate_threshold / 3 (the same share of a uniform spread, 1/3, that the
    ///   gamma rule's 0.2 is) span the degenerate subspace; axis k is flagged when at least
    ///   half of it lies in that subspace (projector diagonal P_kk >= 0.5). An empty group
    ///   flags all three axes. All false when hessian_eigen is off.
    struct RuleFlags {
        std::array<bool, 6> labels1{}, labels2{}, eigen{};
    } rules;

    bool anyDegenerate() const;
};

/// The risk step: labels, counts, gamma, flags and Hessian eigen-analysis of the frame's
/// correspondences at the body pose T_map_body, with the sensor at `sensor_origin` (body frame).
/// Each correspondence is seen from the sensor: its point relative to the sensor in body axes
/// (the rotation labels are torques about the sensor; doc/method.md) and its constraint
/// direction in body axes, flipped toward the sensor — the plane normal; for a line the unit
/// vector from the line to the point; for a point the one from the map point to the scan point.
/// Correspondences with a non-finite value, a zero direction or weight <= 0 are skipped.
RiskReport computeAlignmentRisk(const std::vector<Correspondence>& correspondences, const SE3d& T_map_body,
                                const Vec3d& sensor_origin, const RiskParams& params);
/// The same with the body at the map origin and the sensor at the body origin (correspondences
/// already relative to the sensor, e.g. synthetic scenes).
RiskReport computeAlignmentRisk(const std::vector<Correspondence>& correspondences, const RiskParams& params);

/// The flagged axes as letters in 6-vector order, e.g. "x", "xyaw", "" when none
/// (the `degenerate` column of frames.csv).
std::string degenerateAxes(const RiskReport& report);

/// Flags as letters in 6-vector order (the helper behind degenerateAxes).
std::string axisLetters(const std::array<bool, 6>& flags);

/// Observability-scan colour of a translation label: x red, y green, z blue, anything else
/// (kNoLabel) grey (paper Fig. 4).
std::array<uint8_t, 3> observabilityColor(int translation_label);

}  // namespace superloc::risk
