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
/// The covariance of an information matrix with its unheld directions at kMaxSigma (a
/// pseudo-inverse that stays finite), with the eigen-decomposition it came from.
struct CappedCovariance {
    Mat6d U, C = Mat6d::Zero();
    Vec6d l;  ///< the information's eigenvalues, at least 1 / kMaxSigma^2
    explicit CappedCovariance(const Mat6d& info) {
        const Eigen::SelfAdjointEigenSolver<Mat6d> es(0.5 * (info + info.transpose()));
        const double min_info = 1.0 / (kMaxSigma * kMaxSigma);
        U = es.eigenvectors();
        for (int i = 0; i < 6; ++i) {
            l[i] = std::isfinite(es.eigenvalues()[i]) ? std::max(min_info, es.eigenvalues()[i]) : min_info;
            C.noalias() += U.col(i) * U.col(i).transpose() / l[i];
        }
    }
};
}  // namespace

Mat6d withoutDirection(const Mat6d& H, const Vec6d& u) {
    const Vec6d Hu = H * u;
    const double uHu = u.dot(Hu);
    if (!(uHu > 1e-12 * std::max(1.0, H.diagonal().cwiseAbs().maxCoeff()))) return H;
    const Mat6d out = H - Hu * Hu.transpose() / uHu;
    return 0.5 * (out + out.transpose());
}

std::optional<Vec6d> beyondReach(const Mat6d& carried, const Vec6d& gamma, double weak_gamma, double reach) {
    // Cheap first: no translation axis the risk leaves unheld, or nothing carried.
    if (!(gamma.head<3>().minCoeff() < weak_gamma) || !(carried.trace() > 0)) return std::nullopt;
    const Mat6d C = cappedCovariance(carried);
    const Eigen::SelfAdjointEigenSolver<Mat3d> es(C.topLeftCorner<3, 3>());
    if (es.info() != Eigen::Success || !(es.eigenvalues()[2] > reach * reach)) return std::nullopt;
    const Vec3d u = es.eigenvectors().col(2);
    int k = 0;
    u.cwiseAbs().maxCoeff(&k);
    if (!(gamma[k] < weak_gamma)) return std::nullopt;
    Vec6d u6 = Vec6d::Zero();
    u6.head<3>() = u;
    return u6;
}

Mat6d cappedCovariance(const Mat6d& info) { return CappedCovariance(info).C; }

namespace {
Mat6d aboveNoiseScale(const Mat6d& H, double floor_share) {
    Mat6d S = Mat6d::Zero();
    S.topLeftCorner<3, 3>() = noiseScale(H.topLeftCorner<3, 3>(), floor_share);
    // Rotation: no floor. A torque's noise grows with the lever arm, so a share of the group's
    // trace (dominated by the long yaw and pitch arms) would take roll's real information in a
    // corridor; the rotation degeneracies (yaw over a plane, roll in a round tunnel) are exact
    // zeros of the torques, not a noise level.
    S.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity();
    return S;
}
}  // namespace

Mat6d informationAboveNoise(const Mat6d& H, double floor_share) { return informationAboveNoise(H, floor_share, H); }

Mat6d informationAboveNoise(const Mat6d& H, double floor_share, const Mat6d& G) {
    const Mat6d S = aboveNoiseScale(H, floor_share);
    const Mat6d out = S * G * S;
    return 0.5 * (out + out.transpose());
}

bool Weakness::any() const {
    for (bool w : weak)
        if (w) return true;
    return false;
}

Weakness weakness(const Mat6d& info, const Vec6d& weak_sigma) {
    Weakness out;
    const CappedCovariance cc(info);
    // The std per axis over the eigen-directions that make at least 5 % of it: the marginal,
    // without the unheld corridor axis's thousandth along z turning 1 km into a metre of z.
    for (int k = 0; k < 6; ++k) {
        double var = 0;
        for (int i = 0; i < 6; ++i) {
            const double u2 = cc.U(k, i) * cc.U(k, i);
            if (u2 >= 0.05) var += u2 / cc.l[i];
        }
        out.sigma[k] = std::min(kMaxSigma, std::sqrt(var));
    }
    const Mat6d& C = cc.C;
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
    // The carried translation covariance's weak directions, once per frame (scanPart uses them
    // at the risk step and again at commit).
    weak_dirs_.clear();
    const auto I = carried_ ? poseInformation(*carried_) : std::nullopt;
    if (!I) return;
    const Mat3 Ct = CappedCovariance(*I).C.topLeftCorner<3, 3>();
    const Eigen::SelfAdjointEigenSolver<Mat3> ec(0.5 * (Ct + Ct.transpose()));
    for (int i = 0; i < 3; ++i)
        if (ec.eigenvalues()[i] > weak_xyz_ * weak_xyz_) weak_dirs_.push_back(ec.eigenvectors().col(i));
}

Mat6d EstimateInformation::scanPart(const Mat6d& H) const {
    const double tr = H.topLeftCorner<3, 3>().trace();
    if (weak_dirs_.empty() || !(tr > 0)) return H;
    Mat6d P = Mat6d::Identity();
    for (const Eigen::Vector3d& u : weak_dirs_)
        if (u.dot(H.topLeftCorner<3, 3>() * u) < floor_share_ * tr) P.topLeftCorner<3, 3>() -= u * u.transpose();
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
    weak_dirs_.clear();
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

std::optional<Vec6d> EstimateInformation::motionVariance(double dt, const Mat3d& R_map_imu) const {
    if (!carried_ || !(dt > 0)) return std::nullopt;
    // The speed-bias block's covariance given the pose (conditioning on the pose is what a
    // relative motion needs: its uncertainty is what the velocity and bias add over dt).
    const Eigen::Matrix<double, 9, 9> Hss = 0.5 * (carried_->bottomRightCorner<9, 9>() +
                                                   carried_->bottomRightCorner<9, 9>().transpose());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> es(Hss);
    if (es.info() != Eigen::Success) return std::nullopt;
    const Eigen::Matrix<double, 9, 1> l = es.eigenvalues().cwiseMax(1e-12);
    const Eigen::Matrix<double, 9, 9> C = es.eigenvectors() * l.cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
    const Mat3d Cv = R_map_imu.transpose() * C.topLeftCorner<3, 3>() * R_map_imu;  // map -> body
    Vec6d v;
    v << dt * dt * Cv.diagonal(), dt * dt * C.bottomRightCorner<3, 3>().diagonal();
    return v;
}

void EstimateInformation::reset() {
    prior_.reset();
    carried_.reset();
    weak_dirs_.clear();
}

}  // namespace superloc::fusion
