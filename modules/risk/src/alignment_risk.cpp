// The risk step (doc/method.md §1): Jacobians, observability labels, counts, confidence gamma.
#include <superloc/risk/alignment_risk.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace superloc::risk {
namespace {

/// Index (0..2) of the component of v with the largest magnitude; ties go to the lower index.
int argmaxAbs(const Vec3d& v) {
    int best = 0;
    for (int k = 1; k < 3; ++k)
        if (std::abs(v[k]) > std::abs(v[best])) best = k;
    return best;
}

/// Index of the second-largest |component| of v (ties to the lower index), or -1 when it is 0.
int secondAbs(const Vec3d& v, int first) {
    int best = -1;
    for (int k = 0; k < 3; ++k)
        if (k != first && v[k] != 0 && (best < 0 || std::abs(v[k]) > std::abs(v[best]))) best = k;
    return best;
}

/// The correspondence seen from the sensor (see computeAlignmentRisk): its point relative to
/// the sensor and its constraint direction, both in body axes.
struct SensorView {
    Vec3d p, n;
};

SensorView sensorView(const Correspondence& c, const SE3d& T_map_body, const Vec3d& origin) {
    SensorView v;
    v.p = c.p - origin;
    const Vec3d x = T_map_body * c.p;
    Vec3d n;
    switch (c.type) {
        case FeatureType::Plane: n = c.n; break;
        case FeatureType::Line: {
            const Vec3d e = x - c.q;
            n = e - e.dot(c.n) * c.n;
            break;
        }
        default: n = x - c.q; break;
    }
    n = T_map_body.linear().transpose() * n;
    v.n = n.dot(v.p) > 0 ? Vec3d(-n) : n;  // toward the sensor
    return v;
}

bool usable(const SensorView& v, double weight) {
    return v.p.allFinite() && v.n.allFinite() && std::isfinite(weight) && weight > 0 && v.n.squaredNorm() > 1e-24;
}

/// Paper eq. (7)-(8): gamma within one group of three labels, scaled so that a uniform spread
/// gives 1: gamma_k = min(1, 3 N_k / (N_1 + N_2 + N_3)); an empty group gives 0. (With two
/// rotation labels per correspondence a uniform spread still gives 3 (2/3) / 2 = 1.)
void groupConfidence(const Vec6d& counts, int first, Vec6d& gamma) {
    const double total = counts.segment<3>(first).sum();
    for (int k = first; k < first + 3; ++k)
        gamma[k] = total > 0 ? std::min(1.0, 3.0 * counts[k] / total) : 0.0;
}

/// RiskReport::RuleFlags::eigen for one 3x3 information block (axes first..first+2).
void eigenRule(const Eigen::Matrix3d& block, int first, double threshold, std::array<bool, 6>& flags) {
    const double trace = block.trace();
    if (!(trace > 0) || !block.allFinite()) {
        for (int k = first; k < first + 3; ++k) flags[k] = true;
        return;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(block / trace);
    Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 3; ++i)
        if (es.eigenvalues()[i] < threshold / 3.0) P += es.eigenvectors().col(i) * es.eigenvectors().col(i).transpose();
    for (int k = 0; k < 3; ++k) flags[first + k] = P(k, k) >= 0.5;
}

/// H's lower triangle += w J J^T. The products and sums of Eigen's rankUpdate on the lower
/// triangle (column i: (w J_i) J_k for k >= i), so the result is bit-identical, written out for a
/// 6 x 6: Eigen's general path sized at run time was 11 % of the per-frame risk and weighting
/// (doc/results.md "Cost of the risk and the weighting").
void addLowerRankOne(Mat6d& H, const Vec6d& J, double w) {
    for (int i = 0; i < 6; ++i) {
        const double a = w * J[i];
        for (int k = i; k < 6; ++k) H(k, i) += a * J[k];
    }
}

}  // namespace

bool RiskReport::anyDegenerate() const {
    for (bool d : degenerate)
        if (d) return true;
    return false;
}

RiskReport computeAlignmentRisk(const std::vector<Correspondence>& correspondences, const RiskParams& params) {
    return computeAlignmentRisk(correspondences, SE3d::Identity(), Vec3d::Zero(), params);
}

RiskReport computeAlignmentRisk(const std::vector<Correspondence>& correspondences, const SE3d& T_map_body,
                                const Vec3d& sensor_origin, const RiskParams& params) {
    RiskReport r;
    const size_t n = correspondences.size();
    r.translation_label.assign(n, kNoLabel);
    r.rotation_label.assign(n, kNoLabel);
    r.rotation_label2.assign(n, kNoLabel);
    if (params.keep_jacobians) r.jacobians.assign(n, Vec6d::Zero());
    // Rotation counts with one and with two labels per correspondence (RuleFlags).
    Vec6d counts1 = Vec6d::Zero(), counts2 = Vec6d::Zero();

    for (size_t i = 0; i < n; ++i) {
        const Correspondence& c = correspondences[i];
        const SensorView v = sensorView(c, T_map_body, sensor_origin);
        if (!usable(v, c.weight)) {
            r.skipped++;
            continue;
        }
        // Paper eq. (4): J_i = [p_i x n_i ; n_i]; stored translation first: [n_i ; p_i x n_i].
        const Vec3d normal = v.n.normalized();
        const Vec3d torque = v.p.cross(normal);
        const double w = params.weighted_labels ? c.weight : 1.0;

        // Table I of the paper: the translation label is the axis of largest |n_i . e_k|, the
        // rotation label the axis of largest |(p_i x n_i) . e_k|. Each counts w.
        const int t = argmaxAbs(normal);
        r.translation_label[i] = static_cast<int8_t>(t);
        r.counts[t] += w;
        // A point on the line through the sensor along its normal has no lever arm: it
        // constrains no rotation and gets no rotation label.
        if (torque.squaredNorm() > 1e-24) {
            const int rot = argmaxAbs(torque);
            counts1[3 + rot] += w;
            counts2[3 + rot] += w;
            // The torques of a surface with normal n span the plane orthogonal to n: its two
            // rotation axes (released reference code: top-2 rotation labels).
            const int rot2 = secondAbs(torque, rot);
            if (rot2 >= 0) counts2[3 + rot2] += w;
            r.rotation_label[i] = static_cast<int8_t>(3 + rot);
            if (params.rotation_labels == 2 && rot2 >= 0) r.rotation_label2[i] = static_cast<int8_t>(3 + rot2);
        }
        r.used_by_type[static_cast<size_t>(c.type) % 3]++;

        Vec6d J;
        J << normal, torque;
        if (params.keep_jacobians) r.jacobians[i] = J;
        // Paper eq. (5)-(6): C = sum J_i J_i^T (weighted like the labels).
        if (params.hessian_eigen) addLowerRankOne(r.hessian, J, w);
        r.weight_sum += w;
    }

    // Paper eq. (7)-(8), per group (doc/method.md §1 step 5), and the 0.2 rule of §III-B, for both label
    // schemes; `gamma` is the configured one.
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
        eigenRule(r.hessian.bottomRightCorner<3, 3>(), 3, params.degenerate_threshold, r.rules.eigen);
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
