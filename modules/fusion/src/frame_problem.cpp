#include <ceres/ceres.h>
#include <superloc/fusion/frame_problem.h>
#include "window_terms.h"
#include <superloc/fusion/imu_factor.h>
#include <superloc/fusion/pose_prior_factor.h>
#include <superloc/fusion/relative_pose_factor.h>
#include <superloc/fusion/pose_manifold.h>
#include <superloc/fusion/scan_factor.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace superloc::fusion {

using detail::Mat30d;
using detail::marginalizeInformation;
using detail::imuWindowTerms;
using detail::WindowTerm;

StatePrior fixedStatePrior(const FrameState& s, const FusionParams& params) {
    StatePrior p;
    p.T_ref = s.T_map_imu();
    for (int k = 0; k < 9; ++k) p.sb_ref[k] = s.speed_bias[k];
    Eigen::Matrix<double, 15, 1> w;
    w << Vec3d::Constant(1.0 / params.prev_pose_sigma_xyz),
        Vec3d::Constant(1.0 / (params.prev_pose_sigma_rot_deg * M_PI / 180.0)),
        Vec3d::Constant(1.0 / params.prev_velocity_sigma), Vec3d::Constant(1.0 / params.prev_acc_bias_sigma),
        Vec3d::Constant(1.0 / params.prev_gyro_bias_sigma);
    p.sqrt_info = w.asDiagonal();
    return p;
}

namespace {

/// Ceres' Levenberg-Marquardt step for step (default Solver::Options but those set in
/// solveFrameWithCeres: Jacobi scaling fixed at iteration 0, LM regularization diag(J^T J)/radius
/// clamped to [1e-6, 1e32], radius from 1e4, accepted if the relative decrease exceeds 1e-3,
/// then radius /= max(1/3, 1 - (2 rho - 1)^3), else radius /= 2, 4, 8, ...; function and
/// parameter tolerances tested on each candidate before it is accepted, the gradient tolerance
/// 1e-10 after each accepted step) on a problem given by `linearize(x, H, g)` (its cost; H = J^T J and g = J^T r in the tangent when
/// not null), `plus(x, delta, out)` (the manifold's) and `ambient(x)` (the parameters as Ceres
/// stores them: the tolerances are measured on those). Mat / Vec: the tangent's matrix and
/// vector types (fixed-size for the 6-D pose). x ends at the solution.
template <class Mat, class Vec, class State, class Linearize, class Plus, class Ambient>
SolveSummary levenbergMarquardt(State& x, int max_iterations, Linearize&& linearize, Plus&& plus, Ambient&& ambient) {
    SolveSummary out;
    Mat H;
    Vec g;
    double cost = linearize(x, &H, &g);
    out.initial_cost = out.final_cost = cost;
    if (!std::isfinite(cost) || !H.allFinite() || !g.allFinite()) return out;  // Ceres: FAILURE
    const Eigen::Index n = g.size();
    auto xa = ambient(x);
    State cand = x;
    const auto gradientMaxNorm = [&] {
        plus(x, Vec(-g), cand);
        return (xa - ambient(cand)).template lpNorm<Eigen::Infinity>();
    };
    const Vec scale = (Vec::Ones(n).array() + H.diagonal().array().sqrt()).inverse();
    double radius = 1e4, decrease = 2.0, x_norm = -1.0;  // Ceres leaves x_norm unset until a step
    int iterations = 0, invalid = 0;  // completed iterations (Ceres' summary.iterations - 1)
    bool successful = true;  // iteration 0
    while (true) {
        // FinalizeIterationAndCheckIfMinimizerCanContinue.
        if (iterations >= max_iterations) break;
        if (successful && gradientMaxNorm() <= 1e-10) break;
        if (radius <= 1e-32) break;
        const Mat Hs = scale.asDiagonal() * H * scale.asDiagonal();
        const Vec gs = scale.cwiseProduct(g);
        Mat A = Hs;
        A.diagonal() += Hs.diagonal().cwiseMax(1e-6).cwiseMin(1e32) / radius;
        const Eigen::LLT<Mat> llt(A);
        const Vec step = llt.info() == Eigen::Success ? Vec(llt.solve(-gs)) : Vec(Vec::Zero(n));
        const double model_change = -(step.dot(gs) + 0.5 * step.dot(Hs * step));
        if (llt.info() != Eigen::Success || !(model_change > 0.0)) {
            // Invalid step: shrink the region and solve again; five in a row is a failure.
            if (++invalid >= 5) return out;
            radius /= decrease;
            decrease *= 2.0;
            successful = false;
            ++iterations;
            continue;
        }
        invalid = 0;
        plus(x, Vec(step.cwiseProduct(scale)), cand);
        double cand_cost = linearize(cand, nullptr, nullptr);
        if (!std::isfinite(cand_cost)) cand_cost = std::numeric_limits<double>::max();
        const auto ca = ambient(cand);
        if ((xa - ca).norm() <= 1e-8 * (x_norm + 1e-8)) break;  // parameter tolerance
        if (std::abs(cost - cand_cost) <= 1e-8 * cost) break;   // function tolerance
        const double rho = (cost - cand_cost) / model_change;
        if (rho > 1e-3) {
            x = cand;
            xa = ca;
            x_norm = xa.norm();
            cost = linearize(x, &H, &g);
            radius = std::min(1e16, radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)));
            decrease = 2.0;
            successful = true;
        } else {
            radius /= decrease;
            decrease *= 2.0;
            successful = false;
        }
        ++iterations;
    }
    out.usable = true;
    out.iterations = iterations;
    out.final_cost = cost;
    return out;
}

/// The scan-only problem (no IMU factor, no prior: real data without IMU, the start check's
/// seeds, the searches' hypotheses) on the 6-D tangent. The normal equations are accumulated
/// residual by residual (ScanFactor::linearize), so no N x 7 Jacobian is stored: about 2x faster
/// per solve at ~2000 correspondences than in a Ceres problem (KITTI: 0.31 -> 0.14 ms), the same
/// solution to rounding (test FrameProblem.ScanOnlyMatchesCeres).
SolveSummary solveScanOnly(const ScanFactor& scan, double* pose, int max_iterations) {
    using Vec7d = Eigen::Matrix<double, 7, 1>;
    static const PoseManifold manifold;
    Vec7d x = Eigen::Map<const Vec7d>(pose);
    const SolveSummary out = levenbergMarquardt<Mat6d, Vec6d>(
        x, max_iterations, [&](const Vec7d& s, Mat6d* H, Vec6d* g) { return scan.linearize(s.data(), H, g); },
        [&](const Vec7d& s, const Vec6d& d, Vec7d& o) { manifold.Plus(s.data(), d.data(), o.data()); },
        [](const Vec7d& s) -> const Vec7d& { return s; });
    if (out.usable) std::copy_n(x.data(), 7, pose);
    return out;
}

/// The window's problem (solveFrame's factors: the IMU factor and the previous state's prior,
/// odom_alt's relative prior with its robust loss, a prior on the current pose, the scan's
/// normal equations) solved without building a Ceres problem: Ceres' Levenberg-Marquardt step
/// for step as solveScanOnly runs it (SPARSE_NORMAL_CHOLESKY's system solved densely: the same
/// steps to rounding), over the free blocks' tangent: with IMU the previous pose and
/// speed-bias and the current ones (30), without it the current pose (the previous held, as
/// solveFrameWithCeres sets it constant). A robust loss enters as Ceres' Corrector applies it
/// (residual and Jacobian rescaled by sqrt(rho'), with the second-order term where rho'' > 0).
/// The marginal, when asked, is the Gauss-Newton information at the solution, as marginalize()
/// evaluates it from a Ceres problem.
SolveSummary solveWindow(const FrameProblemInputs& in, const FusionParams& params, bool with_imu) {
    static const PoseManifold manifold;
    using MatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 30, 30>;
    using VecX = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 32, 1>;
    std::vector<WindowTerm> terms;
    if (with_imu) terms = imuWindowTerms(in, params, *in.prev);
    std::unique_ptr<ceres::LossFunction> loss;
    if (in.prior) {
        const double c = params.active.prior_kernel_sigmas;
        switch (robustKernelFromString(params.active.prior_kernel)) {
            case RobustKernel::Huber: loss = std::make_unique<ceres::HuberLoss>(c); break;
            case RobustKernel::Cauchy: loss = std::make_unique<ceres::CauchyLoss>(c); break;
            case RobustKernel::None: break;
        }
        terms.push_back({std::unique_ptr<ceres::CostFunction>(RelativePoseFactor::Create(in.prior->delta, in.prior->sqrt_info)),
                         {0, 2}, loss.get()});
    }
    if (in.cur_pose_prior)
        terms.push_back({std::unique_ptr<ceres::CostFunction>(
                             PosePriorFactor::Create(in.cur_pose_prior->first, in.cur_pose_prior->second)),
                         {2}});
    const ScanFactor* scan = in.scan && in.scan->num_residuals() > 0 ? in.scan : nullptr;

    // The free blocks' tangent offsets (-1: held).
    constexpr int kAmbient[4] = {7, 9, 7, 9}, kTangent[4] = {6, 9, 6, 9};
    int offset[4] = {-1, -1, -1, -1};
    int n = 0, na = 0;
    for (int b = 0; b < 4; ++b)
        if (with_imu || b == 2) offset[b] = n, n += kTangent[b], na += kAmbient[b];
    using Window = std::array<FrameState, 2>;  // prev, cur
    const auto blocks = [](const Window& w, const double* block[4]) {
        block[0] = w[0].pose, block[1] = w[0].speed_bias, block[2] = w[1].pose, block[3] = w[1].speed_bias;
    };
    const auto ambient = [&](const Window& w) {
        const double* block[4];
        blocks(w, block);
        VecX v(na);
        int k = 0;
        for (int b = 0; b < 4; ++b)
            if (offset[b] >= 0) v.segment(k, kAmbient[b]) = Eigen::Map<const Eigen::VectorXd>(block[b], kAmbient[b]), k += kAmbient[b];
        return v;
    };
    const auto plus = [&](const Window& w, const VecX& delta, Window& out) {
        out = w;
        const double* from[4];
        blocks(w, from);
        double* to[4] = {out[0].pose, out[0].speed_bias, out[1].pose, out[1].speed_bias};
        for (int b = 0; b < 4; ++b) {
            if (offset[b] < 0) continue;
            if (kAmbient[b] == 7)
                manifold.Plus(from[b], delta.data() + offset[b], to[b]);
            else
                for (int k = 0; k < 9; ++k) to[b][k] = from[b][k] + delta[offset[b] + k];
        }
    };
    // The cost at w, and (H, g) over the free tangent when asked; NaN when a factor fails.
    detail::TermResidual r;
    detail::TermJacobian Jt;
    const auto linearize = [&](const Window& w, MatX* H, VecX* g) {
        const double* block[4];
        blocks(w, block);
        double cost = 0;
        if (H) H->setZero(n, n), g->setZero(n);
        for (const WindowTerm& t : terms) {
            if (!detail::evaluateTerm(t, block, offset, n, r, H ? &Jt : nullptr)) return std::numeric_limits<double>::quiet_NaN();
            const double sq = r.squaredNorm();
            // Ceres' Corrector (residual_block.cc / corrector.cc).
            double sqrt_rho1 = 1.0, residual_scaling = 1.0, alpha_sq_norm = 0.0;
            if (t.loss) {
                double rho[3];
                t.loss->Evaluate(sq, rho);
                cost += 0.5 * rho[0];
                sqrt_rho1 = std::sqrt(rho[1]);
                residual_scaling = sqrt_rho1;
                if (sq != 0.0 && rho[2] > 0.0) {
                    const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * sq * rho[2] / rho[1]);
                    residual_scaling = sqrt_rho1 / (1.0 - alpha);
                    alpha_sq_norm = alpha / sq;
                }
            } else {
                cost += 0.5 * sq;
            }
            if (!H) continue;
            if (t.loss) {
                if (alpha_sq_norm != 0.0) Jt -= alpha_sq_norm * r * (r.transpose() * Jt);
                Jt *= sqrt_rho1;
            }
            H->noalias() += Jt.transpose() * Jt;
            g->noalias() += Jt.transpose() * (residual_scaling * r);
        }
        if (scan) {
            Mat6d Hs;
            Vec6d gs;
            cost += scan->linearize(w[1].pose, H ? &Hs : nullptr, H ? &gs : nullptr);
            if (H) H->block<6, 6>(offset[2], offset[2]) += Hs, g->segment<6>(offset[2]) += gs;
        }
        return cost;
    };

    Window x{*in.prev, *in.cur};
    MatX H_final;
    const auto linearizeKeeping = [&](const Window& w, MatX* H, VecX* g) {
        const double c = linearize(w, H, g);
        if (H) H_final = *H;  // the accepted state's, for the marginal
        return c;
    };
    SolveSummary out = levenbergMarquardt<MatX, VecX>(x, params.max_iterations, linearizeKeeping, plus, ambient);
    if (!out.usable) return out;
    *in.prev = x[0], *in.cur = x[1];
    if (with_imu && in.marginalize && H_final.rows() == 30) out.marginal = marginalizeInformation(Mat30d(H_final), *in.cur);
    for (FrameState* st : {in.cur, in.prev}) Eigen::Map<Eigen::Vector4d>(st->pose + 3).normalize();
    return out;
}
}  // namespace

SolveSummary solveFrame(const FrameProblemInputs& in, const FusionParams& params) {
    const bool with_imu = in.imu != nullptr && in.imu->dt() > 0;
    if (!with_imu && !in.prior && !in.cur_pose_prior && in.scan && in.scan->num_residuals() > 0) {
        SolveSummary out = solveScanOnly(*in.scan, in.cur->pose, params.max_iterations);
        Eigen::Map<Eigen::Vector4d> q(in.cur->pose + 3);
        q.normalize();
        return out;
    }
    if (!with_imu && !in.prior && !in.cur_pose_prior) return SolveSummary{};  // nothing to solve
    return solveWindow(in, params, with_imu);
}


}  // namespace superloc::fusion
