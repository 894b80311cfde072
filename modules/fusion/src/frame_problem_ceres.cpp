// The frame's problem built and solved by Ceres (frame_problem.h: solveFrameWithCeres): the
// reference the written-out solve (frame_problem.cpp) is tested and benchmarked against.
#include <ceres/ceres.h>
#include <superloc/fusion/frame_problem.h>
#include "window_terms.h"
#include <superloc/fusion/imu_factor.h>
#include <superloc/fusion/pose_manifold.h>
#include <superloc/fusion/pose_prior_factor.h>
#include <superloc/fusion/relative_pose_factor.h>
#include <superloc/fusion/scan_factor.h>
#include <superloc/fusion/state_prior_factor.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <optional>

namespace superloc::fusion {

using detail::Mat30d;
using detail::marginalizeInformation;

namespace {

/// The problem's Jacobian over [prev pose, prev speed-bias, cur pose, cur speed-bias] at the
/// states' values (tangent coordinates), robust losses applied.
std::optional<ceres::CRSMatrix> windowJacobian(ceres::Problem& problem, FrameState& prev, FrameState& cur) {
    ceres::Problem::EvaluateOptions eo;
    eo.parameter_blocks = {prev.pose, prev.speed_bias, cur.pose, cur.speed_bias};
    eo.apply_loss_function = true;
    eo.num_threads = 1;
    ceres::CRSMatrix J;
    if (!problem.Evaluate(eo, nullptr, nullptr, nullptr, &J) || J.num_cols != 30) return std::nullopt;
    return J;
}

/// J^T J of a window Jacobian (30 columns) over each row's non-zeros only (a scan row touches the
/// 6 columns of the current pose): 36 products per scan residual instead of a dense 30 x 30
/// update. Each pair of a row once, into the lower triangle, then mirrored: J_ra J_rb and J_rb
/// J_ra are the same product, summed over the rows in the same order, so the same bits as both
/// halves summed.
Mat30d normalMatrix(const ceres::CRSMatrix& J) {
    Mat30d H = Mat30d::Zero();
    for (int r = 0; r < J.num_rows; ++r)
        for (int a = J.rows[r]; a < J.rows[r + 1]; ++a) {
            const int ca = J.cols[a];
            const double va = J.values[a];
            for (int b = a; b < J.rows[r + 1]; ++b) {
                const int cb = J.cols[b];
                H(std::max(ca, cb), std::min(ca, cb)) += va * J.values[b];
            }
        }
    H.triangularView<Eigen::StrictlyUpper>() = H.transpose();
    return H;
}

std::optional<StatePrior> marginalize(ceres::Problem& problem, FrameState& prev, FrameState& cur) {
    const auto J = windowJacobian(problem, prev, cur);
    if (!J) return std::nullopt;
    return marginalizeInformation(normalMatrix(*J), cur);
}
}  // namespace

namespace {
/// The scan's N residuals as Ceres sees them through 7: at each evaluation the scan's normal
/// equations in the pose's tangent (ScanFactor::linearize: H = J^T J, g = J^T r, cost c) are
/// factored H = P^T L D L^T P (pivoted LDL^T, semi-definite allowed), and the block reports the
/// Jacobian [D^1/2 L^T P; 0] with the residual [D^-1/2 L^-1 P g; sqrt(2c - |.|^2)]: the same
/// J^T J, J^T r and cost, so the same Gauss-Newton / Levenberg-Marquardt steps, Jacobi scaling and
/// marginal as the N x 7 block, to rounding (test FrameProblem.CondensedScanIsTheScanToRounding).
/// Ceres then forms a 7 x 7 product instead of the N x 7 one (one frame: 2000 rows).
class CondensedScan : public ceres::CostFunction {
   public:
    explicit CondensedScan(const ScanFactor& scan) : scan_(scan) {
        set_num_residuals(7);
        mutable_parameter_block_sizes()->push_back(7);
    }
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
        const double* x = parameters[0];
        const bool jacobian = jacobians && jacobians[0];
        if (!jacobian) {
            // A candidate's cost (Ceres evaluates the residuals again with the Jacobian where it
            // accepts a step): only the cost needs to be right, so all of it in the last residual.
            const double cost = scan_.linearize(x, nullptr, nullptr);
            if (!std::isfinite(cost)) return false;
            for (int k = 0; k < 6; ++k) residuals[k] = 0.0;
            residuals[6] = std::sqrt(2.0 * cost);
            return true;
        }
        Mat6d H;
        Vec6d g;
        const double cost = scan_.linearize(x, &H, &g);
        if (!std::isfinite(cost) || !H.allFinite() || !g.allFinite()) return false;
        const Eigen::LDLT<Mat6d> ldlt(H);
        if (ldlt.info() != Eigen::Success) return false;
        const Vec6d D = ldlt.vectorD();
        const double tiny = 1e-14 * std::max(1.0, D.cwiseAbs().maxCoeff());
        // y = L^-1 P g; r = D^-1/2 y where D > 0 (g has nothing along a null direction of H).
        const Mat6d P = ldlt.transpositionsP() * Mat6d::Identity();
        Vec6d y = P * g;
        ldlt.matrixL().solveInPlace(y);
        Vec6d sqrtD;
        double explained = 0;
        for (int k = 0; k < 6; ++k) {
            sqrtD[k] = D[k] > tiny ? std::sqrt(D[k]) : 0.0;
            residuals[k] = sqrtD[k] > 0 ? y[k] / sqrtD[k] : 0.0;
            explained += residuals[k] * residuals[k];
        }
        residuals[6] = std::sqrt(std::max(0.0, 2.0 * cost - explained));
        {
            // Tangent Jacobian Jt = D^1/2 L^T P (6 x 6), then ambient as ScanFactor::Evaluate:
            // translation columns as they are, rotation columns times 2 M(q)^T.
            const Mat6d Jt = sqrtD.asDiagonal() * Mat6d(ldlt.matrixU()) * P;
            Eigen::Map<Eigen::Matrix<double, 7, 7, Eigen::RowMajor>> J(jacobians[0]);
            J.setZero();
            J.topLeftCorner<6, 3>() = Jt.leftCols<3>();
            J.block<6, 4>(0, 3) = Jt.rightCols<3>() * rotationTangentToAmbient(x + 3);
        }
        return true;
    }

   private:
    const ScanFactor& scan_;
};
}  // namespace

SolveSummary solveFrameWithCeres(const FrameProblemInputs& in, const FusionParams& params) {
    const bool with_imu = in.imu != nullptr && in.imu->dt() > 0;
    ceres::Problem::Options popt;
    popt.cost_function_ownership = ceres::TAKE_OWNERSHIP;
    popt.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(popt);
    static PoseManifold manifold;  // stateless
    FrameState& cur = *in.cur;
    FrameState& prev = *in.prev;
    problem.AddParameterBlock(cur.pose, 7, &manifold);

    // Scan-to-map residuals (one block, IRLS weights already set), condensed to their normal
    // equations (CondensedScan): the factor is owned by the caller.
    if (in.scan && in.scan->num_residuals() > 0) problem.AddResidualBlock(new CondensedScan(*in.scan), nullptr, cur.pose);

    if (with_imu) {
        // IMU factor (Forster eq. 45) between prev and cur; prev held by priors (two-state window).
        problem.AddParameterBlock(prev.pose, 7, &manifold);
        problem.AddParameterBlock(prev.speed_bias, 9);
        problem.AddParameterBlock(cur.speed_bias, 9);
        problem.AddResidualBlock(
            ImuFactor::Create(*in.imu, in.g_map, in.acc_bias_rw, in.gyro_bias_rw), nullptr,
            prev.pose, prev.speed_bias, cur.pose, cur.speed_bias);
        problem.AddResidualBlock(
            StatePriorFactor::Create(in.prev_prior ? *in.prev_prior : fixedStatePrior(prev, params)), nullptr,
            prev.pose, prev.speed_bias);
    }

    if (in.prior) {
        // Relative-pose prior from odom_alt (paper §III-C), information chosen by the caller.
        if (!with_imu) problem.AddParameterBlock(prev.pose, 7, &manifold);
        // Its residual is whitened, so the loss's scale is in sigmas (Cauchy: rho(s) = c^2
        // log(1 + s/c^2)). The name was checked by FusionParams::validate.
        ceres::LossFunction* loss = nullptr;
        const double c = params.active.prior_kernel_sigmas;
        switch (robustKernelFromString(params.active.prior_kernel)) {
            case RobustKernel::Huber: loss = new ceres::HuberLoss(c); break;
            case RobustKernel::Cauchy: loss = new ceres::CauchyLoss(c); break;
            case RobustKernel::None: break;
        }
        problem.AddResidualBlock(
            RelativePoseFactor::Create(in.prior->delta, in.prior->sqrt_info), loss, prev.pose,
            cur.pose);
        if (!with_imu) problem.SetParameterBlockConstant(prev.pose);
    }

    if (in.cur_pose_prior)
        problem.AddResidualBlock(
            PosePriorFactor::Create(in.cur_pose_prior->first, in.cur_pose_prior->second), nullptr, cur.pose);

    SolveSummary out;
    if (problem.NumResidualBlocks() == 0) return out;
    ceres::Solver::Options opt;
    // Block-sparse normal equations: the N x 7 scan block costs N*49 flops instead of the N*32^2
    // of a dense QR over all 32 columns (office with IMU: 1.3 vs 3.3 ms per frame).
    opt.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    opt.max_num_iterations = params.max_iterations;
    opt.num_threads = 1;
    opt.minimizer_progress_to_stdout = false;
    opt.logging_type = ceres::SILENT;
    opt.function_tolerance = 1e-8;
    opt.parameter_tolerance = 1e-8;
    ceres::Solver::Summary summary;
    ceres::Solve(opt, &problem, &summary);
    out.usable = summary.IsSolutionUsable();
    out.iterations = static_cast<int>(summary.iterations.size()) - 1;
    out.initial_cost = summary.initial_cost;
    out.final_cost = summary.final_cost;
    if (with_imu && in.marginalize && out.usable) out.marginal = marginalize(problem, prev, cur);
    // Keep the quaternions exactly unit.
    for (FrameState* s : {in.cur, in.prev}) {
        Eigen::Map<Eigen::Vector4d> q(s->pose + 3);
        q.normalize();
    }
    return out;
}


}  // namespace superloc::fusion
