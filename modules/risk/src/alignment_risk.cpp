// The risk step (doc/method.md §1): Jacobians, observability labels, counts, confidence gamma.
#include <superloc/risk/alignment_risk.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace superloc::risk {
namespace {

/// Index (0..2) of the component of v with the largest magnitude; ties go to the lower index.
int argmaxAbs(const double* v) {
    int best = 0;
    for (int k = 1; k < 3; ++k)
        if (std::abs(v[k]) > std::abs(v[best])) best = k;
    return best;
}

/// Index of the second-largest |component| of v (ties to the lower index), or -1 when it is 0.
int secondAbs(const double* v, int first) {
    int best = -1;
    for (int k = 0; k < 3; ++k)
        if (k != first && v[k] != 0 && (best < 0 || std::abs(v[k]) > std::abs(v[best]))) best = k;
    return best;
}

/// A block of correspondences seen from the sensor (see computeAlignmentRisk), one array per
/// coordinate: each one's point relative to the sensor and its constraint direction toward the
/// sensor, both in body axes, then that direction normalized and its torque about the sensor.
/// Three passes: the directions, then all square roots and divisions at once (packed: one
/// correspondence's root and divisions in a chain held the loop up), then the labels and sums.
/// Written on scalars in the order Eigen evaluates the same expressions (x = R p + t;
/// n = R^T m; u = n / |n|; p x u), so the bits are those of the Eigen form per correspondence;
/// Eigen's mix of packed and scalar temporaries there stalled on store forwarding
/// (doc/results.md "Cost of the risk and the weighting").
struct SensorBlock {
    static constexpr size_t kSize = 64;
    Eigen::Array<double, kSize, 3> p, n, u, torque;
    Eigen::Array<double, kSize, 1> sq;
    bool ok[kSize];

    /// Pass 1 for correspondence c into row j; ok[j] false when it is skipped: a non-finite
    /// value, a zero direction or weight <= 0.
    void direction(size_t j, const Correspondence& c, const double* R, const double* t,
                   const double* origin) {
        const double* cp = c.p.data();
        double v[3];
        for (int k = 0; k < 3; ++k) v[k] = cp[k] - origin[k];
        double m[3];
        if (c.type == FeatureType::Plane) {
            for (int k = 0; k < 3; ++k) m[k] = c.n[k];
        } else {
            // x = R p + t (R column-major: R[k + 3 j] = R(k, j)).
            double e[3];
            for (int k = 0; k < 3; ++k) {
                const double x = R[k] * cp[0] + R[k + 3] * cp[1] + R[k + 6] * cp[2] + t[k];
                e[k] = x - c.q[k];
            }
            if (c.type == FeatureType::Line) {
                const double* d = c.n.data();
                const double s = e[0] * d[0] + e[1] * d[1] + e[2] * d[2];
                for (int k = 0; k < 3; ++k) m[k] = e[k] - s * d[k];
            } else {
                for (int k = 0; k < 3; ++k) m[k] = e[k];
            }
        }
        double w[3];
        for (int k = 0; k < 3; ++k)
            w[k] = R[3 * k] * m[0] + R[3 * k + 1] * m[1] + R[3 * k + 2] * m[2];
        if (w[0] * v[0] + w[1] * v[1] + w[2] * v[2] > 0)
            for (double& x : w) x = -x;
        const double s = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        const bool finite = std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) &&
                            std::isfinite(w[0]) && std::isfinite(w[1]) && std::isfinite(w[2]);
        ok[j] = finite && std::isfinite(c.weight) && c.weight > 0 && s > 1e-24;
        for (int k = 0; k < 3; ++k) p(j, k) = v[k], n(j, k) = w[k];
        sq[j] = ok[j] ? s : 1.0;
    }

    /// Pass 2 over rows 0..m-1: u = n / |n|, torque = p x u.
    void normalize(size_t m) {
        const auto len = sq.head(m).sqrt().eval();
        for (int k = 0; k < 3; ++k) u.col(k).head(m) = n.col(k).head(m) / len;
        torque.col(0).head(m) =
            p.col(1).head(m) * u.col(2).head(m) - p.col(2).head(m) * u.col(1).head(m);
        torque.col(1).head(m) =
            p.col(2).head(m) * u.col(0).head(m) - p.col(0).head(m) * u.col(2).head(m);
        torque.col(2).head(m) =
            p.col(0).head(m) * u.col(1).head(m) - p.col(1).head(m) * u.col(0).head(m);
    }
};

/// Paper eq. (7)-(8): gamma within one group of three labels, scaled so that a uniform spread
/// gives 1: gamma_k = min(1, 3 N_k / (N_1 + N_2 + N_3)); an empty group gives 0. (With two
/// rotation labels per correspondence a uniform spread still gives 3 (2/3) / 2 = 1.)
void groupConfidence(const Vec6d& counts, int first, Vec6d& gamma) {
    const double total = counts.segment<3>(first).sum();
    for (int k = first; k < first + 3; ++k)
        gamma[k] = total > 0 ? std::min(1.0, 3.0 * counts[k] / total) : 0.0;
}

/// RiskReport::RuleFlags::eigen for one 3x3 information block (axes first..first+2).
void eigenRule(const Eigen::Matrix3d& block, int first, double threshold,
               std::array<bool, 6>& flags) {
    const double trace = block.trace();
    if (!(trace > 0) || !block.allFinite()) {
        for (int k = first; k < first + 3; ++k) flags[k] = true;
        return;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(block / trace);
    Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 3; ++i)
        if (es.eigenvalues()[i] < threshold / 3.0)
            P += es.eigenvectors().col(i) * es.eigenvectors().col(i).transpose();
    for (int k = 0; k < 3; ++k) flags[first + k] = P(k, k) >= 0.5;
}

}  // namespace

bool RiskReport::anyDegenerate() const {
    for (bool d : degenerate)
        if (d) return true;
    return false;
}

RiskReport computeAlignmentRisk(const std::vector<Correspondence>& correspondences,
                                const RiskParams& params) {
    return computeAlignmentRisk(correspondences, SE3d::Identity(), Vec3d::Zero(), params);
}

RiskReport computeAlignmentRisk(const std::vector<Correspondence>& correspondences,
                                const SE3d& T_map_body, const Vec3d& sensor_origin,
                                const RiskParams& params) {
    RiskReport r;
    const size_t n = correspondences.size();
    r.translation_label.assign(n, kNoLabel);
    r.rotation_label.assign(n, kNoLabel);
    r.rotation_label2.assign(n, kNoLabel);
    if (params.keep_jacobians) r.jacobians.assign(n, Vec6d::Zero());
    // Translation counts, rotation counts with one and with two labels per correspondence
    // (RuleFlags), the Hessian's lower triangle: accumulated on locals.
    double counts_t[3] = {0, 0, 0}, counts_r1[3] = {0, 0, 0}, counts_r2[3] = {0, 0, 0};
    // H's lower triangle, h<k><i> = H(k, i), as 21 scalars: an array (or Eigen's matrix) was
    // read and written in pairs from values stored one by one, stalling on store forwarding.
    double h00 = 0, h10 = 0, h20 = 0, h30 = 0, h40 = 0, h50 = 0, h11 = 0, h21 = 0, h31 = 0, h41 = 0,
           h51 = 0, h22 = 0, h32 = 0, h42 = 0, h52 = 0, h33 = 0, h43 = 0, h53 = 0, h44 = 0, h54 = 0,
           h55 = 0;
    double weight_sum = 0;
    const Mat3d R_map_body = T_map_body.linear();  // contiguous: the transform's block is not
    const double* R = R_map_body.data();
    const Vec3d t_map = T_map_body.translation();
    SensorBlock blk;

    for (size_t b = 0; b < n; b += SensorBlock::kSize) {
        const size_t m = std::min(SensorBlock::kSize, n - b);
        for (size_t j = 0; j < m; ++j)
            blk.direction(j, correspondences[b + j], R, t_map.data(), sensor_origin.data());
        blk.normalize(m);
        for (size_t j = 0; j < m; ++j) {
            const size_t i = b + j;
            const Correspondence& c = correspondences[i];
            if (!blk.ok[j]) {
                r.skipped++;
                continue;
            }
            // Paper eq. (4): J_i = [p_i x n_i ; n_i]; stored translation first: [n_i ; p_i x n_i].
            const double normal[3] = {blk.u(j, 0), blk.u(j, 1), blk.u(j, 2)};
            const double torque[3] = {blk.torque(j, 0), blk.torque(j, 1), blk.torque(j, 2)};
            const double w = params.weighted_labels ? c.weight : 1.0;

            // Table I of the paper: the translation label is the axis of largest |n_i . e_k|, the
            // rotation label the axis of largest |(p_i x n_i) . e_k|. Each counts w.
            const int tl = argmaxAbs(normal);
            r.translation_label[i] = static_cast<int8_t>(tl);
            counts_t[tl] += w;
            // A point on the line through the sensor along its normal has no lever arm: it
            // constrains no rotation and gets no rotation label.
            if (torque[0] * torque[0] + torque[1] * torque[1] + torque[2] * torque[2] > 1e-24) {
                const int rot = argmaxAbs(torque);
                counts_r1[rot] += w;
                counts_r2[rot] += w;
                // The torques of a surface with normal n span the plane orthogonal to n: its two
                // rotation axes (released reference code: top-2 rotation labels).
                const int rot2 = secondAbs(torque, rot);
                if (rot2 >= 0) counts_r2[rot2] += w;
                r.rotation_label[i] = static_cast<int8_t>(3 + rot);
                if (params.rotation_labels == 2 && rot2 >= 0)
                    r.rotation_label2[i] = static_cast<int8_t>(3 + rot2);
            }
            r.used_by_type[static_cast<size_t>(c.type) % 3]++;

            if (params.keep_jacobians)
                r.jacobians[i] << normal[0], normal[1], normal[2], torque[0], torque[1], torque[2];
            // Paper eq. (5)-(6): C = sum J_i J_i^T (weighted like the labels).
            // The products and sums of Eigen's rankUpdate on the lower triangle (column i:
            // (w J_i) J_k for k >= i), so the bits are those of H.selfadjointView().rankUpdate(J,
            // w).
            if (params.hessian_eigen) {
                const double j0 = normal[0], j1 = normal[1], j2 = normal[2], j3 = torque[0],
                             j4 = torque[1], j5 = torque[2];
                const double a0 = w * j0, a1 = w * j1, a2 = w * j2, a3 = w * j3, a4 = w * j4,
                             a5 = w * j5;
                h00 += a0 * j0, h10 += a0 * j1, h20 += a0 * j2, h30 += a0 * j3, h40 += a0 * j4,
                    h50 += a0 * j5;
                h11 += a1 * j1, h21 += a1 * j2, h31 += a1 * j3, h41 += a1 * j4, h51 += a1 * j5;
                h22 += a2 * j2, h32 += a2 * j3, h42 += a2 * j4, h52 += a2 * j5;
                h33 += a3 * j3, h43 += a3 * j4, h53 += a3 * j5;
                h44 += a4 * j4, h54 += a4 * j5;
                h55 += a5 * j5;
            }
            weight_sum += w;
        }
    }
    r.weight_sum = weight_sum;
    Vec6d counts1 = Vec6d::Zero(), counts2 = Vec6d::Zero();
    for (int k = 0; k < 3; ++k) {
        r.counts[k] = counts_t[k];
        counts1[3 + k] = counts_r1[k];
        counts2[3 + k] = counts_r2[k];
    }
    if (params.hessian_eigen) {
        const double lower[21] = {h00, h10, h20, h30, h40, h50, h11, h21, h31, h41, h51,
                                  h22, h32, h42, h52, h33, h43, h53, h44, h54, h55};
        const double* hp = lower;
        for (int i = 0; i < 6; ++i)
            for (int k = i; k < 6; ++k) r.hessian(k, i) = *hp++;
    }

    // Paper eq. (7)-(8), per group (doc/method.md §1 step 5), and the 0.2 rule of §III-B, for both
    // label schemes; `gamma` is the configured one.
    Vec6d gamma1 = Vec6d::Zero(), gamma2 = Vec6d::Zero();
    counts1.head<3>() = counts2.head<3>() = r.counts.head<3>();
    groupConfidence(counts1, 0, gamma1);
    groupConfidence(counts1, 3, gamma1);
    groupConfidence(counts2, 0, gamma2);
    groupConfidence(counts2, 3, gamma2);
    r.counts.tail<3>() = (params.rotation_labels == 2 ? counts2 : counts1).tail<3>();
    r.gamma = params.rotation_labels == 2 ? gamma2 : gamma1;
    for (int k = 0; k < 6; ++k) {
        r.degenerate[k] = r.gamma[k] < params.degenerate_threshold;
        r.rules.labels1[k] = gamma1[k] < params.degenerate_threshold;
        r.rules.labels2[k] = gamma2[k] < params.degenerate_threshold;
    }

    if (params.hessian_eigen) {
        r.hessian = r.hessian.selfadjointView<Eigen::Lower>();
        const Eigen::SelfAdjointEigenSolver<Mat6d> es(r.hessian);
        r.eigenvalues = es.eigenvalues();
        r.eigenvectors = es.eigenvectors();
        r.condition_number = r.eigenvalues[0] > 0 ? r.eigenvalues[5] / r.eigenvalues[0]
                                                  : std::numeric_limits<double>::infinity();
        if (r.weight_sum > 0) {
            // The translation block of H is sum w n n^T: per unit weight it has trace 1.
            const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> et(
                r.hessian.topLeftCorner<3, 3>() / r.weight_sum);
            r.translation_eigenvalues = et.eigenvalues().cwiseMax(0.0);
            Vec3d v = et.eigenvectors().col(0);
            Eigen::Index k = 0;
            v.cwiseAbs().maxCoeff(&k);
            r.weakest_translation = v[k] < 0 ? Vec3d(-v) : v;
        }
        eigenRule(r.hessian.topLeftCorner<3, 3>(), 0, params.degenerate_threshold, r.rules.eigen);
        eigenRule(r.hessian.bottomRightCorner<3, 3>(), 3, params.degenerate_threshold,
                  r.rules.eigen);
    }
    return r;
}

std::string axisLetters(const std::array<bool, 6>& flags) {
    std::string s;
    for (int k = 0; k < 6; ++k)
        if (flags[k]) s += kAxisNames[k];
    return s;
}

std::string degenerateAxes(const RiskReport& report) { return axisLetters(report.degenerate); }

std::array<uint8_t, 3> observabilityColor(int translation_label) {
    switch (translation_label) {
        case 0:
            return {255, 0, 0};
        case 1:
            return {0, 255, 0};
        case 2:
            return {0, 0, 255};
        default:
            return {128, 128, 128};
    }
}

}  // namespace superloc::risk
