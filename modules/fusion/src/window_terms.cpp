// The IMU window's factors one by one (window_terms.h).
#include "window_terms.h"

#include <superloc/fusion/imu_factor.h>
#include <superloc/fusion/pose_manifold.h>
#include <superloc/fusion/state_prior_factor.h>

#include <Eigen/Eigenvalues>

namespace superloc::fusion::detail {

std::optional<StatePrior> asStatePrior(Mat15d M, const FrameState& cur) {
    // Tangent translation is in the map frame, the prior's error in the reference body axes:
    // e = A d with A = diag(R^T, I, I), so the information is A M A^T.
    const SE3d T = cur.T_map_imu();
    Mat15d A = Mat15d::Identity();
    A.topLeftCorner<3, 3>() = T.linear().transpose();
    M = A * M * A.transpose();
    M = 0.5 * (M + M.transpose());
    const Eigen::SelfAdjointEigenSolver<Mat15d> es(M);
    if (es.info() != Eigen::Success || !es.eigenvalues().allFinite()) return std::nullopt;
    StatePrior p;
    p.T_ref = T;
    for (int k = 0; k < 9; ++k) p.sb_ref[k] = cur.speed_bias[k];
    // L^T L = M with L = D^1/2 V^T (eigenvalues rounded up to 0).
    p.sqrt_info = es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
    return p;
}

std::optional<StatePrior> marginalizeInformation(const Mat30d& H, const FrameState& cur) {
    const Mat15d Hpp = H.topLeftCorner<15, 15>(), Hcc = H.bottomRightCorner<15, 15>();
    const Mat15d Hcp = H.bottomLeftCorner<15, 15>();
    // Hpp is positive definite: the previous state always has its prior.
    const Eigen::LDLT<Mat15d> ldlt(Hpp);
    if (ldlt.info() != Eigen::Success) return std::nullopt;
    return asStatePrior(Hcc - Hcp * ldlt.solve(Hcp.transpose()), cur);
}

bool evaluateTerm(const WindowTerm& t, const double* const block[4], const int col[4], int cols, TermResidual& r,
                  TermJacobian* J) {
    static const PoseManifold manifold;
    constexpr int kAmbient[4] = {7, 9, 7, 9};
    const int m = t.f->num_residuals();
    if (m > kMaxTermResiduals || t.blocks.size() > 4) return false;
    const double* params[4];
    double* jp[4];
    double jac[4][kMaxTermResiduals * 9];
    for (size_t k = 0; k < t.blocks.size(); ++k) {
        const int b = t.blocks[k];
        params[k] = block[b];
        jp[k] = J && col[b] >= 0 ? jac[k] : nullptr;
    }
    r.resize(m);
    if (!t.f->Evaluate(params, r.data(), J ? jp : nullptr)) return false;
    if (!J) return true;
    J->setZero(m, cols);
    for (size_t k = 0; k < t.blocks.size(); ++k) {
        const int b = t.blocks[k];
        if (col[b] < 0) continue;
        using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
        const Eigen::Map<const RowMat> Ja(jac[k], m, kAmbient[b]);
        if (kAmbient[b] == 7) {
            double P[42];
            manifold.PlusJacobian(block[b], P);
            J->block(0, col[b], m, 6) = Ja * Eigen::Map<const Eigen::Matrix<double, 7, 6, Eigen::RowMajor>>(P);
        } else {
            J->block(0, col[b], m, 9) = Ja;
        }
    }
    return true;
}

std::optional<Eigen::Matrix<double, Eigen::Dynamic, 30>> directWindowJacobian(const std::vector<WindowTerm>& terms,
                                                                             FrameState& prev, FrameState& cur) {
    const double* const block[4] = {prev.pose, prev.speed_bias, cur.pose, cur.speed_bias};
    const int col[4] = {0, 6, 15, 21};
    int rows = 0;
    for (const auto& t : terms) rows += t.f->num_residuals();
    Eigen::Matrix<double, Eigen::Dynamic, 30> J(rows, 30);
    int row = 0;
    TermResidual r;
    TermJacobian Jt;
    for (const auto& t : terms) {
        if (!evaluateTerm(t, block, col, 30, r, &Jt)) return std::nullopt;
        J.middleRows(row, Jt.rows()) = Jt;
        row += static_cast<int>(Jt.rows());
    }
    if (!J.allFinite()) return std::nullopt;
    return J;
}

std::vector<WindowTerm> imuWindowTerms(const FrameProblemInputs& in, const FusionParams& params, const FrameState& prev) {
    std::vector<WindowTerm> t;
    t.push_back({std::unique_ptr<ceres::CostFunction>(
                     ImuFactor::Create(*in.imu, in.g_map, in.acc_bias_rw, in.gyro_bias_rw)),
                 {0, 1, 2, 3}});
    t.push_back({std::unique_ptr<ceres::CostFunction>(
                     StatePriorFactor::Create(in.prev_prior ? *in.prev_prior : fixedStatePrior(prev, params))),
                 {0, 1}});
    return t;
}

}  // namespace superloc::fusion::detail
