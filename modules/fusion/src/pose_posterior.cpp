// The reported pose's covariance (pose_posterior.h, doc/method.md §4).
#include <superloc/core/se3.h>
#include <superloc/fusion/estimate_information.h>
#include <superloc/fusion/pose_posterior.h>
#include <superloc/fusion/prior_weight.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>

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

namespace {
/// One cell of mapErrorShare's grid: the translation information of its correspondences and
/// their weighted sum of positions (the centre is x / w).
struct ShareCell {
    Mat3d H = Mat3d::Zero();
    Vec3d x = Vec3d::Zero();
    double w = 0;
};

/// Sums cells on a grid of `edge` metres, keyed by their points: a flat open-addressing table
/// (a scan's 2 000 correspondences in a few microseconds, nothing allocated per point).
class CellGrid {
   public:
    CellGrid(size_t n, double edge) : inv_(1.0 / edge) {
        while (cap_ < 2 * n) cap_ *= 2;
        keys_.assign(cap_, ~0ull);
        slot_.assign(cap_, 0);
        cells_.reserve(n);
    }
    ShareCell& at(const Vec3d& x) {
        const auto q = [this](double v) {
            return static_cast<uint64_t>(static_cast<int64_t>(std::floor(v * inv_)) + (1 << 20)) & 0x1FFFFFu;
        };
        const uint64_t key = (q(x.x()) << 42) | (q(x.y()) << 21) | q(x.z());
        size_t i = static_cast<size_t>((key * 0x9E3779B97F4A7C15ULL) >> 20) & (cap_ - 1);
        while (keys_[i] != ~0ull && keys_[i] != key) i = (i + 1) & (cap_ - 1);
        if (keys_[i] == ~0ull) {
            keys_[i] = key;
            slot_[i] = static_cast<uint32_t>(cells_.size());
            cells_.emplace_back();
        }
        return cells_[slot_[i]];
    }
    std::vector<ShareCell>& cells() { return cells_; }

   private:
    double inv_;
    size_t cap_ = 16;
    std::vector<uint64_t> keys_;
    std::vector<uint32_t> slot_;
    std::vector<ShareCell> cells_;
};

/// The cells of `edge` metres that `in`'s cells (by their weighted centres) fall in, summed.
std::vector<ShareCell> coarsen(const std::vector<ShareCell>& in, double edge) {
    CellGrid g(in.size(), edge);
    for (const ShareCell& c : in) {
        ShareCell& o = g.at(c.x / c.w);
        o.H += c.H;
        o.x += c.x;
        o.w += c.w;
    }
    return std::move(g.cells());
}
}  // namespace

Mat3d mapErrorShare(const std::vector<Correspondence>& corr, const SE3d& T_map_imu, double cell, double length,
                    double floor_share) {
    if (!(cell > 0) || !(length > 0) || !std::isfinite(cell + length)) return Mat3d::Identity();
    // The correspondences summed on the grid (each cell's translation information at its
    // weighted centre), coarsened while the scan spans more than kMapShareMaxCells cells.
    double edge = cell;
    CellGrid grid(corr.size(), edge);
    Mat3d H = Mat3d::Zero();
    for (const Correspondence& c : corr) {
        if (!(c.weight > 0) || !c.q.allFinite() || !c.n.allFinite() || c.q.cwiseAbs().maxCoeff() > 1e6) continue;
        Mat3d h;
        switch (c.type) {
            case FeatureType::Plane: h = c.n * c.n.transpose(); break;
            case FeatureType::Line: h = Mat3d::Identity() - c.n * c.n.transpose(); break;
            default: h = Mat3d::Identity(); break;
        }
        h *= c.weight;
        H += h;
        ShareCell& s = grid.at(c.q);
        s.H += h;
        s.x += c.weight * c.q;
        s.w += c.weight;
    }
    std::vector<ShareCell> cells = std::move(grid.cells());
    if (cells.empty()) return Mat3d::Identity();
    while (cells.size() > static_cast<size_t>(kMapShareMaxCells)) cells = coarsen(cells, edge *= 2);
    // The held directions (above the noise floor) and the others.
    const Eigen::SelfAdjointEigenSolver<Mat3d> es(H);
    if (es.info() != Eigen::Success || !(es.eigenvalues()[2] > 0)) return Mat3d::Identity();
    const double noise = std::max(1e-12, floor_share) * H.trace();
    Mat3d Hinv = Mat3d::Zero(), unheld = Mat3d::Zero();
    for (int k = 0; k < 3; ++k) {
        const Vec3d v = es.eigenvectors().col(k);
        if (es.eigenvalues()[k] > noise)
            Hinv += v * v.transpose() / es.eigenvalues()[k];
        else
            unheld += v * v.transpose();
    }
    // S = sum_ij rho_ij H_i H_j over the cells (rho below 1e-4 left out: beyond 4.3 lengths).
    std::vector<Vec3d> xc(cells.size());
    for (size_t i = 0; i < cells.size(); ++i) xc[i] = cells[i].x / cells[i].w;
    const double inv2l2 = 1.0 / (2.0 * length * length), cutoff = -std::log(1e-4) / inv2l2;
    Mat3d S = Mat3d::Zero();
    for (size_t i = 0; i < cells.size(); ++i) {
        const Mat3d& Hi = cells[i].H;
        S.noalias() += Hi * Hi;
        Mat3d cross = Mat3d::Zero();
        for (size_t j = i + 1; j < cells.size(); ++j) {
            const double d2 = (xc[i] - xc[j]).squaredNorm();
            if (d2 < cutoff) cross.noalias() += std::exp(-d2 * inv2l2) * cells[j].H;
        }
        const Mat3d P = Hi * cross;
        S += P + P.transpose();
    }
    Mat3d M = Hinv * S * Hinv;
    M = 0.5 * (M + M.transpose());
    const Eigen::SelfAdjointEigenSolver<Mat3d> em(M);
    M = em.eigenvectors() * em.eigenvalues().cwiseMax(0.0).cwiseMin(1.0).asDiagonal() * em.eigenvectors().transpose();
    M += unheld;
    const Mat3d R = T_map_imu.linear();
    return R.transpose() * M * R;
}

Vec6d PosePosterior::floor(const FloorGeometry& g) const {
    Vec6d f = floor_;
    if (g.imu_deskewed && floor_xyz_imu_ >= 0) f.head<3>().setConstant(floor_xyz_imu_);
    f.tail<3>() = f.tail<3>().cwiseMax(mapRotationFloor(g.H, map_sigma_));
    return f;
}

Mat6d PosePosterior::floorCovariance(const FloorGeometry& g) const {
    const Vec6d f = floor(g);
    Mat6d C = Mat6d::Zero();
    C.diagonal() = f.cwiseAbs2();
    if (g.map_share && floor_xyz_imu_ >= 0) {
        // The map's part of the position's floor as this scan takes it; the rest (deskew,
        // timing) on every axis.
        const double m2 = floor_xyz_imu_ * floor_xyz_imu_;
        for (int k = 0; k < 3; ++k) C(k, k) = std::max(0.0, f[k] * f[k] - m2);
        C.topLeftCorner<3, 3>() += m2 * *g.map_share;
    }
    return C;
}

Mat6d driftTiltCovariance(const Mat6d& C, double tilt) {
    Mat6d out = Mat6d::Zero();
    if (!(tilt > 0)) return out;
    const Eigen::SelfAdjointEigenSolver<Mat3d> es(0.5 * (C.topLeftCorner<3, 3>() + C.topLeftCorner<3, 3>().transpose()));
    if (es.info() != Eigen::Success) return out;
    const double l = es.eigenvalues()[2];
    if (!(l > 0) || !(l < 0.01 * kMaxSigma * kMaxSigma)) return out;
    const Vec3d u = es.eigenvectors().col(2);
    const double s = std::sin(tilt);
    out.topLeftCorner<3, 3>() = s * s * l * (Mat3d::Identity() - u * u.transpose());
    return out;
}

Mat6d PosePosterior::covariance(const Mat6d& info, const FloorGeometry& g) const {
    const Mat6d Ci = cappedCovariance(info);
    Mat6d C = Ci + driftTiltCovariance(Ci, drift_tilt_) + floorCovariance(g);
    return 0.5 * (C + C.transpose());
}

PosePosterior::Update PosePosterior::update(const FrameProblemInputs& in, const FusionParams& params,
                                            const Mat6d& H_in, const FloorGeometry& floor,
                                            const std::optional<ScanReach>& reach) const {
    Update u;
    u.floor = floor;
    u.T_ref = in.cur->T_map_imu();
    for (int k = 0; k < 9; ++k) u.sb_ref[k] = in.cur->speed_bias[k];
    Mat6d H_added = H_in;
    // The scan along a direction the pose carried beyond the association's reach is left out,
    // once what was carried is known (beyondReach).
    const auto leaveOut = [&](const Mat6d& carried_pose) {
        if (!reach) return false;
        const auto dir = beyondReach(carried_pose, reach->gamma, reach->weak_gamma, reach->reach);
        if (dir) H_added = withoutDirection(H_added, *dir);
        return dir.has_value();
    };
    Mat6d pose_info = Mat6d::Zero(), carried_pose = Mat6d::Zero();
    if (in.imu && in.imu->dt() > 0) {
        FrameProblemInputs p = in;
        p.prev_prior = prior_ ? &*prior_ : nullptr;
        // An odom_alt the solve weighed above what it is worth: the information of the estimate
        // it made (the window's sandwich, with and without the scan), not that of the estimate
        // it should have made. The scan enters the sandwich, so leaving part of it out means a
        // second sandwich.
        if (in.prior && in.prior->worth) {
            auto w = imuWindowStateInformationWeighed(p, params, *in.prior->worth, H_added);
            if (w && leaveOut(poseInformation(w->without_scan).value_or(Mat6d::Zero())))
                w = imuWindowStateInformationWeighed(p, params, *in.prior->worth, H_added);
            if (w) {
                u.with_imu = true;
                u.info_without_scan = w->without_scan;
                u.info = w->with_scan;
            }
        } else if (const auto carried = imuWindowStateInformation(p, params)) {
            u.with_imu = true;
            u.info_without_scan = *carried;
            leaveOut(poseInformation(*carried).value_or(Mat6d::Zero()));
            u.info = *carried;
            u.info.topLeftCorner<6, 6>() += H_added;
        }
        if (u.with_imu) pose_info = poseInformation(u.info).value_or(H_added);
    } else if (pose_prior_ && in.prior && in.prev) {
        // Without IMU: the last pose's information carried through odom_alt's relative prior,
        // the previous pose eliminated (Schur complement of the 12 x 12 joint information).
        // Without IMU odom_alt alone carries the pose across the frame: at what it is worth.
        const Mat6d W = in.prior->worth ? *in.prior->worth : Mat6d(in.prior->sqrt_info.transpose() * in.prior->sqrt_info);
        const Mat6d Jp = relativeJacobianPrev(in.prev->T_map_imu().inverse() * in.cur->T_map_imu());
        const Mat6d App = pose_prior_->second + Jp.transpose() * W * Jp;
        const Eigen::LDLT<Mat6d> ldlt(0.5 * (App + App.transpose()));
        if (ldlt.info() == Eigen::Success) {
            const Mat6d Apc = Jp.transpose() * W;
            Mat6d carried = W - Apc.transpose() * ldlt.solve(Apc);
            carried = 0.5 * (carried + carried.transpose());
            if (carried.allFinite()) {
                carried_pose = carried;
                leaveOut(carried_pose);
            }
        }
    }
    if (!u.with_imu) {
        pose_info = H_added + carried_pose;
        u.info.topLeftCorner<6, 6>() = pose_info;
        u.info_without_scan.topLeftCorner<6, 6>() = carried_pose;
    }
    u.cov = covariance(pose_info, floor);
    return u;
}

Mat6d PosePosterior::Update::carriedPoseInformation() const {
    if (with_imu) return poseInformation(info_without_scan).value_or(Mat6d::Zero());
    return info_without_scan.topLeftCorner<6, 6>();
}

PosePosterior::Update PosePosterior::withoutScan(const Update& u) const {
    Update w = u;
    w.info = u.info_without_scan;
    w.cov = covariance(u.carriedPoseInformation(), u.floor);
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
