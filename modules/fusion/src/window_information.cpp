// What the IMU window knows of the current state (frame_problem.h: imuWindowStateInformation,
// imuWindowStateInformationWeighed, poseInformation), from the window's factors evaluated one by
// one (window_terms.h).
#include "window_terms.h"

#include <superloc/fusion/frame_problem.h>
#include <superloc/fusion/relative_pose_factor.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <memory>
#include <vector>

namespace superloc::fusion {

using detail::asStatePrior;
using detail::directWindowJacobian;
using detail::imuWindowTerms;
using detail::marginalizeInformation;
using detail::Mat30d;
using detail::WindowTerm;

std::optional<Mat15d> imuWindowStateInformation(const FrameProblemInputs& in, const FusionParams& params) {
    if (!in.imu || !(in.imu->dt() > 0) || !in.prev || !in.cur) return std::nullopt;
    // Copies: the problem's blocks are ours, and the caller's states stay as they are.
    FrameState prev = *in.prev, cur = *in.cur;
    std::vector<WindowTerm> terms = imuWindowTerms(in, params, prev);
    if (in.prior)  // odom_alt's relative motion between the two states (PosePosterior)
        terms.push_back({std::unique_ptr<ceres::CostFunction>(
                             RelativePoseFactor::Create(in.prior->delta, in.prior->sqrt_info)),
                         {0, 2}});
    const auto J = directWindowJacobian(terms, prev, cur);
    if (!J) return std::nullopt;
    const auto m = marginalizeInformation(J->transpose() * *J, cur);
    if (!m) return std::nullopt;
    return Mat15d(m->sqrt_info.transpose() * m->sqrt_info);
}

namespace {
/// The current state's information (StatePrior coordinates) of the estimate that weighed the
/// window H_rest + E^T B_s E while its noise is H_rest + E^T B_s B_t^+ B_s E: the inverse of the
/// current-state block of the sandwich H_s^-1 N H_s^-1.
std::optional<Mat15d> sandwichInformation(const Mat30d& Hs, const Mat30d& N, const FrameState& cur) {
    // Jacobi-scaled (the window's blocks span ten decades of information).
    const Eigen::Matrix<double, 30, 1> d = Hs.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const Mat30d Hs_d = d.asDiagonal() * Hs * d.asDiagonal(), N_d = d.asDiagonal() * N * d.asDiagonal();
    const Eigen::LDLT<Mat30d> ldlt(0.5 * (Hs_d + Hs_d.transpose()));
    if (ldlt.info() != Eigen::Success) return std::nullopt;
    const Mat30d X = ldlt.solve(Mat30d::Identity());
    const Mat30d C = d.asDiagonal() * (X * N_d * X) * d.asDiagonal();
    const Mat15d Ccc = 0.5 * (C.bottomRightCorner<15, 15>() + C.bottomRightCorner<15, 15>().transpose());
    const Eigen::LDLT<Mat15d> lc(Ccc);
    if (lc.info() != Eigen::Success || !(lc.vectorD().minCoeff() > 0)) return std::nullopt;
    const auto p = asStatePrior(lc.solve(Mat15d::Identity()), cur);
    if (!p) return std::nullopt;
    return Mat15d(p->sqrt_info.transpose() * p->sqrt_info);
}
}  // namespace

std::optional<WeighedWindowInformation> imuWindowStateInformationWeighed(const FrameProblemInputs& in,
                                                                         const FusionParams& params,
                                                                         const Mat6d& worth, const Mat6d& scan) {
    if (!in.prior || !in.imu || !(in.imu->dt() > 0) || !in.prev || !in.cur) return std::nullopt;
    FrameState prev = *in.prev, cur = *in.cur;
    // The window without odom_alt (IMU factor and the previous state's prior), and odom_alt's
    // error alone (its factor with unit information): its 6 x 30 Jacobian E.
    std::vector<WindowTerm> terms = imuWindowTerms(in, params, prev);
    terms.push_back({std::unique_ptr<ceres::CostFunction>(RelativePoseFactor::Create(in.prior->delta, Mat6d::Identity())),
                     {0, 2}});
    const auto J = directWindowJacobian(terms, prev, cur);
    if (!J || J->rows() < 6) return std::nullopt;
    // The relative factor's 6 rows are the last ones; the others are H_rest's.
    const Eigen::Matrix<double, 6, 30> E = J->bottomRows<6>();
    const Eigen::Matrix<double, Eigen::Dynamic, 30> Jr = J->topRows(J->rows() - 6);
    // The solve weighed odom_alt's error at B_s; it is worth B_t. Its estimate's error is then
    // H_s^-1 (H_rest + E^T B_s B_t^+ B_s E) H_s^-1 (the sandwich), H_s = H_rest + E^T B_s E.
    const Mat6d Bs = in.prior->sqrt_info.transpose() * in.prior->sqrt_info;
    const Eigen::SelfAdjointEigenSolver<Mat6d> et(0.5 * (worth + worth.transpose()));
    if (et.info() != Eigen::Success) return std::nullopt;
    const double tiny = 1e-12 * std::max(1.0, et.eigenvalues().cwiseAbs().maxCoeff());
    Vec6d inv = Vec6d::Zero();
    for (int k = 0; k < 6; ++k) inv[k] = et.eigenvalues()[k] > tiny ? 1.0 / et.eigenvalues()[k] : 0.0;
    const Mat6d Bt_pinv = et.eigenvectors() * inv.asDiagonal() * et.eigenvectors().transpose();
    const Mat30d Hrest = Jr.transpose() * Jr;
    const Mat30d Hodom = E.transpose() * Bs * E, Nodom = E.transpose() * (Bs * Bt_pinv * Bs) * E;
    // The scan on the current pose, weighed by the solve as it is worth: its information in body
    // axes (a right perturbation) is A^T H A in the window's tangent coordinates (translation in
    // the map frame), A = diag(R^T, I).
    Mat6d A = Mat6d::Identity();
    A.topLeftCorner<3, 3>() = cur.T_map_imu().linear().transpose();
    Mat30d Hscan = Mat30d::Zero();
    Hscan.block<6, 6>(15, 15) = A.transpose() * scan * A;
    const auto without = sandwichInformation(Hrest + Hodom, Hrest + Nodom, cur);
    const auto with = sandwichInformation(Hrest + Hscan + Hodom, Hrest + Hscan + Nodom, cur);
    if (!without || !with) return std::nullopt;
    return WeighedWindowInformation{*without, *with};
}

std::optional<Mat6d> poseInformation(const Mat15d& M) {
    const Mat6d Hpp = M.topLeftCorner<6, 6>();
    const Eigen::Matrix<double, 6, 9> Hps = M.topRightCorner<6, 9>();
    const Eigen::Matrix<double, 9, 9> Hss = M.bottomRightCorner<9, 9>();
    const Eigen::LDLT<Eigen::Matrix<double, 9, 9>> ldlt(Hss);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return std::nullopt;
    Mat6d I = Hpp - Hps * ldlt.solve(Hps.transpose());
    I = 0.5 * (I + I.transpose());
    if (!I.allFinite()) return std::nullopt;
    return I;
}

}  // namespace superloc::fusion
