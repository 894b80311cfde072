// The reported pose's covariance (pose_posterior.h, doc/method.md §4).
#include <superloc/core/se3.h>
#include <superloc/fusion/estimate_information.h>
#include <superloc/fusion/pose_posterior.h>
#include <superloc/fusion/prior_weight.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace superloc::fusion {

namespace {
Mat3d skew(const Vec3d& v) {
    Mat3d m;
    m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    return m;
}
}  // namespace

Mat6d relativeJacobianPrev(const SE3d& T_rel) {
    const Mat3d Rt = T_rel.linear().transpose();
    Mat6d J = Mat6d::Zero();
    J.topLeftCorner<3, 3>() = -Rt;
    J.topRightCorner<3, 3>() = Rt * skew(T_rel.translation());
    J.bottomRightCorner<3, 3>() = -Rt;
    return J;
}

double largestStd(const Mat3d& C) {
    return std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Mat3d>(0.5 * (C + C.transpose())).eigenvalues()[2]));
}

Vec3d mapRotationFloor(const Mat6d& H, double map_sigma) {
    Vec3d f = Vec3d::Zero();
    const double tt = H(0, 0) + H(1, 1) + H(2, 2);
    if (!(map_sigma > 0) || !(tt > 0) || !std::isfinite(tt)) return f;
    for (int k = 0; k < 3; ++k) {
        const double rr = H(3 + k, 3 + k);
        if (rr > 0 && std::isfinite(rr)) f[k] = map_sigma / std::sqrt(3.0 * rr / tt);
    }
    return f;
}

Vec6d PosePosterior::floor(const Mat6d& H, bool imu_deskewed) const {
    Vec6d f = floor_;
    if (imu_deskewed && floor_xyz_imu_ >= 0) f.head<3>().setConstant(floor_xyz_imu_);
    f.tail<3>() = f.tail<3>().cwiseMax(mapRotationFloor(H, map_sigma_));
    return f;
}

Mat6d PosePosterior::covariance(const Mat6d& info, const Mat6d& H, bool imu_deskewed) const {
    Mat6d C = cappedCovariance(info);
    C.diagonal() += floor(H, imu_deskewed).cwiseAbs2();
    return 0.5 * (C + C.transpose());
}

PosePosterior::Update PosePosterior::update(const FrameProblemInputs& in, const FusionParams& params,
                                            const Mat6d& H, const Mat6d& H_added, bool imu_deskewed) const {
    Update u;
    u.T_ref = in.cur->T_map_imu();
    for (int k = 0; k < 9; ++k) u.sb_ref[k] = in.cur->speed_bias[k];
    Mat6d pose_info = H_added, carried_pose = Mat6d::Zero();
    if (in.imu && in.imu->dt() > 0) {
        FrameProblemInputs p = in;
        p.prev_prior = prior_ ? &*prior_ : nullptr;
        if (const auto carried = imuWindowStateInformation(p, params)) {
            u.with_imu = true;
            u.info_without_scan = *carried;
            u.info = *carried;
            u.info.topLeftCorner<6, 6>() += H_added;
            if (const auto I = poseInformation(u.info)) pose_info = *I;
        }
    } else if (pose_prior_ && in.prior && in.prev) {
        // Without IMU: the last pose's information carried through odom_alt's relative prior,
        // the previous pose eliminated (Schur complement of the 12 x 12 joint information).
        const Mat6d W = in.prior->sqrt_info.transpose() * in.prior->sqrt_info;
        const Mat6d Jp = relativeJacobianPrev(in.prev->T_map_imu().inverse() * in.cur->T_map_imu());
        const Mat6d App = pose_prior_->second + Jp.transpose() * W * Jp;
        const Eigen::LDLT<Mat6d> ldlt(0.5 * (App + App.transpose()));
        if (ldlt.info() == Eigen::Success) {
            const Mat6d Apc = Jp.transpose() * W;
            Mat6d carried = W - Apc.transpose() * ldlt.solve(Apc);
            carried = 0.5 * (carried + carried.transpose());
            if (carried.allFinite()) pose_info += carried, carried_pose = carried;
        }
    }
    if (!u.with_imu) {
        u.info.topLeftCorner<6, 6>() = pose_info;
        u.info_without_scan.topLeftCorner<6, 6>() = carried_pose;
    }
    u.cov = covariance(pose_info, H, imu_deskewed);
    return u;
}

Mat6d PosePosterior::Update::carriedPoseInformation() const {
    if (with_imu) return poseInformation(info_without_scan).value_or(Mat6d::Zero());
    return info_without_scan.topLeftCorner<6, 6>();
}

PosePosterior::Update PosePosterior::withoutScan(const Update& u, const Mat6d& H, bool imu_deskewed) const {
    Update w = u;
    w.info = u.info_without_scan;
    w.cov = covariance(u.carriedPoseInformation(), H, imu_deskewed);
    return w;
}

void PosePosterior::commit(const Update& u) {
    if (u.with_imu) {
        const Mat15d M = 0.5 * (u.info + u.info.transpose());
        const Eigen::SelfAdjointEigenSolver<Mat15d> es(M);
        if (es.info() != Eigen::Success || !es.eigenvalues().allFinite()) {
            reset();
            return;
        }
        StatePrior p;
        p.T_ref = u.T_ref;
        p.sb_ref = u.sb_ref;
        p.sqrt_info = es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
        prior_ = p;
        pose_prior_.reset();
    } else {
        prior_.reset();
        pose_prior_ = std::make_pair(u.T_ref, Mat6d(u.info.topLeftCorner<6, 6>()));
    }
}

void PosePosterior::reset() {
    prior_.reset();
    pose_prior_.reset();
}

Mat6d sweepCovariance(const std::vector<Correspondence>& corr, const SE3d& T_map_imu, const SweepDeparture& d,
                      double scan_sigma, double floor_share, const Mat6d& carried) {
    if (d.none() || corr.empty()) return Mat6d::Zero();
    // A_g: each residual's fit weight times g at its point's time, as scanInformation's weights.
    std::vector<double> sqrt_wg(corr.size());
    for (size_t i = 0; i < corr.size(); ++i) {
        const double s = std::clamp((double(corr[i].rel_time) + d.T) / d.T, 0.0, 1.0);
        const double g = d.parabola ? 4.0 * s * (1.0 - s) : 1.0 - s;
        sqrt_wg[i] = std::sqrt(std::max(0.0, corr[i].weight) * g);
    }
    const Mat6d H = scanInformation(corr, T_map_imu, scan_sigma);
    const Mat6d A = informationAboveNoise(H, floor_share);
    const Mat6d A_g = informationAboveNoise(H, floor_share, scanInformation(corr, T_map_imu, scan_sigma, &sqrt_wg));
    const Mat6d M = cappedCovariance(A + carried) * A_g;
    const Mat6d cov = M * d.delta.cwiseAbs2().asDiagonal() * M.transpose();
    return cov.allFinite() ? Mat6d(0.5 * (cov + cov.transpose())) : Mat6d::Zero();
}

Mat6d toReported(const Mat6d& C, const SE3d& T_map_imu, const SE3d& T_imu_out) {
    // T_out = T_map_imu Exp(d) T_imu_out: position p + R(u + theta x t), rotation R Exp(theta) R_io
    // = Exp(R theta) R R_io. So dp_map = R u - R [t]x theta, dtheta_map = R theta.
    const Mat3d R = T_map_imu.linear();
    Mat6d J = Mat6d::Zero();
    J.topLeftCorner<3, 3>() = R;
    J.topRightCorner<3, 3>() = -R * skew(T_imu_out.translation());
    J.bottomRightCorner<3, 3>() = R;
    const Mat6d out = J * C * J.transpose();
    return 0.5 * (out + out.transpose());
}

}  // namespace superloc::fusion
