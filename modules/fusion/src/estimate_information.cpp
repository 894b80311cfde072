#include <superloc/fusion/estimate_information.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace superloc::fusion {

namespace {
using Mat3 = Eigen::Matrix3d;

/// S of one group: V diag(sqrt(max(0, l - floor tr) / l)) V^T.
Mat3 noiseScale(const Mat3& block, double floor_share) {
    const double tr = block.trace();
    if (!(tr > 0) || !block.allFinite()) return Mat3::Zero();
    const Eigen::SelfAdjointEigenSolver<Mat3> es(0.5 * (block + block.transpose()));
    Eigen::Vector3d f;
    for (int i = 0; i < 3; ++i) {
        const double l = es.eigenvalues()[i];
        f[i] = l > 0 ? std::sqrt(std::max(0.0, l - floor_share * tr) / l) : 0.0;
    }
    return es.eigenvectors() * f.asDiagonal() * es.eigenvectors().transpose();
}
}  // namespace

Mat6d informationAboveNoise(const Mat6d& H, double floor_share) {
    Mat6d S = Mat6d::Zero();
    S.topLeftCorner<3, 3>() = noiseScale(H.topLeftCorner<3, 3>(), floor_share);
    // Rotation: no floor. A torque's noise grows with the lever arm, so a share of the group's
    // trace (dominated by the long yaw and pitch arms) would take roll's real information in a
    // corridor; the rotation degeneracies (yaw over a plane, roll in a round tunnel) are exact
    // zeros of the torques, not a noise level.
    S.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity();
    const Mat6d out = S * H * S;
    return 0.5 * (out + out.transpose());
}

bool Weakness::any() const {
    for (bool w : weak)
        if (w) return true;
    return false;
}

Weakness weakness(const Mat6d& info, const Vec6d& weak_sigma) {
    Weakness out;
    // Covariance with the unheld directions at kMaxSigma (a pseudo-inverse that stays finite).
    const Eigen::SelfAdjointEigenSolver<Mat6d> es(0.5 * (info + info.transpose()));
    const double min_info = 1.0 / (kMaxSigma * kMaxSigma);
    Mat6d C = Mat6d::Zero();
    for (int i = 0; i < 6; ++i) {
        const double l = std::isfinite(es.eigenvalues()[i]) ? std::max(min_info, es.eigenvalues()[i]) : min_info;
        C.noalias() += es.eigenvectors().col(i) * es.eigenvectors().col(i).transpose() / l;
    }
    // The std per axis over the eigen-directions that make at least 5 % of it: the marginal,
    // without the unheld corridor axis's thousandth along z turning 1 km into a metre of z.
    for (int k = 0; k < 6; ++k) {
        double var = 0;
        for (int i = 0; i < 6; ++i) {
            const double u2 = es.eigenvectors()(k, i) * es.eigenvectors()(k, i);
            const double l = std::isfinite(es.eigenvalues()[i]) ? std::max(min_info, es.eigenvalues()[i]) : min_info;
            if (u2 >= 0.05) var += u2 / l;
        }
        out.sigma[k] = std::min(kMaxSigma, std::sqrt(var));
    }
    // Per group: the directions of the marginal covariance and their std.
    for (int g = 0; g < 2; ++g) {
        const Mat3 Cg = C.block<3, 3>(3 * g, 3 * g);
        const Eigen::SelfAdjointEigenSolver<Mat3> eg(0.5 * (Cg + Cg.transpose()));
        Eigen::Vector3d w;
        for (int i = 0; i < 3; ++i) {
            const double var = std::max(0.0, eg.eigenvalues()[i]);
            const double lim = weak_sigma[3 * g];
            w[i] = var / (var + lim * lim);
        }
        out.G.block<3, 3>(3 * g, 3 * g) =
            eg.eigenvectors() * w.cwiseSqrt().asDiagonal() * eg.eigenvectors().transpose();
        const Mat3 P = eg.eigenvectors() * w.asDiagonal() * eg.eigenvectors().transpose();
        for (int k = 0; k < 3; ++k) out.weak[3 * g + k] = P(k, k) >= 0.5;
    }
    return out;
}

void EstimateInformation::predict(const FrameProblemInputs& in, const FusionParams& params) {
    FrameProblemInputs p = in;
    p.prev_prior = prior_ ? &*prior_ : nullptr;
    carried_ = imuWindowStateInformation(p, params);
}

Mat6d EstimateInformation::scanPart(const Mat6d& H) const {
    if (!carried_) return H;
    const auto I = poseInformation(*carried_);
    const double tr = H.topLeftCorner<3, 3>().trace();
    if (!I || !(tr > 0)) return H;
    // The carried translation covariance's weak directions (pseudo-inverse at kMaxSigma).
    const Eigen::SelfAdjointEigenSolver<Mat6d> es(0.5 * (*I + I->transpose()));
    const double min_info = 1.0 / (kMaxSigma * kMaxSigma);
    Mat6d C = Mat6d::Zero();
    for (int i = 0; i < 6; ++i)
        C.noalias() += es.eigenvectors().col(i) * es.eigenvectors().col(i).transpose() /
                       std::max(min_info, std::isfinite(es.eigenvalues()[i]) ? es.eigenvalues()[i] : min_info);
    const Eigen::SelfAdjointEigenSolver<Mat3> ec(0.5 * (C.topLeftCorner<3, 3>() + C.topLeftCorner<3, 3>().transpose()));
    Mat6d P = Mat6d::Identity();
    for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d u = ec.eigenvectors().col(i);
        if (!(ec.eigenvalues()[i] > weak_xyz_ * weak_xyz_)) continue;
        if (u.dot(H.topLeftCorner<3, 3>() * u) >= floor_share_ * tr) continue;  // real information
        P.topLeftCorner<3, 3>() -= u * u.transpose();
    }
    const Mat6d out = P * H * P;
    return 0.5 * (out + out.transpose());
}

Mat6d EstimateInformation::information(const Mat6d& H_scan) const {
    if (!carried_) return H_scan;
    const Mat6d H = scanPart(H_scan);
    Mat15d M = *carried_;
    M.topLeftCorner<6, 6>() += H;
    const auto I = poseInformation(M);
    return I ? *I : H;
}

void EstimateInformation::commit(const FrameState& cur, const Mat6d& H_scan) {
    if (!carried_) {
        prior_.reset();
        return;
    }
    const Mat6d H = scanPart(H_scan);
    Mat15d M = *carried_;
    M.topLeftCorner<6, 6>() += H;
    M = 0.5 * (M + M.transpose());
    carried_.reset();
    const Eigen::SelfAdjointEigenSolver<Mat15d> es(M);
    if (es.info() != Eigen::Success || !es.eigenvalues().allFinite()) {
        prior_.reset();
        return;
    }
    StatePrior p;
    p.T_ref = cur.T_map_imu();
    for (int k = 0; k < 9; ++k) p.sb_ref[k] = cur.speed_bias[k];
    p.sqrt_info = es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
    prior_ = p;
}

void EstimateInformation::reset() {
    prior_.reset();
    carried_.reset();
}

}  // namespace superloc::fusion
