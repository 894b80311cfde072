#include <superloc/core/se3.h>
#include <superloc/fusion/pose_manifold.h>
#include <superloc/fusion/scan_factor.h>

#include <cmath>
#include <stdexcept>

namespace superloc::fusion {


RobustKernel robustKernelFromString(const std::string& s) {
    if (s == "none") return RobustKernel::None;
    if (s == "huber") return RobustKernel::Huber;
    if (s == "cauchy") return RobustKernel::Cauchy;
    throw std::invalid_argument("unknown robust kernel '" + s + "' (use none, huber or cauchy)");
}

double robustWeight(RobustKernel kernel, double r, double k) {
    switch (kernel) {
        case RobustKernel::Huber: return r <= k ? 1.0 : k / r;
        case RobustKernel::Cauchy: return 1.0 / (1.0 + (r * r) / (k * k));
        case RobustKernel::None: break;
    }
    return 1.0;
}

int residualDim(FeatureType t) {
    return t == FeatureType::Plane ? 1 : t == FeatureType::Line ? 2 : 3;
}

namespace {
// Two unit vectors orthogonal to d (and to each other).
void lineBasis(const Vec3d& d, Vec3d& e1, Vec3d& e2) {
    const Vec3d a = std::abs(d.x()) < 0.9 ? Vec3d::UnitX() : Vec3d::UnitY();
    e1 = d.cross(a).normalized();
    e2 = d.cross(e1);
}

/// The map-frame directions a residual of `c` measures along (plane: its normal; line: two
/// directions across it; point: the map axes) into a; returns residualDim.
int residualAxes(const Correspondence& c, Vec3d* a) {
    switch (c.type) {
        case FeatureType::Plane: a[0] = c.n; return 1;
        case FeatureType::Line: lineBasis(c.n, a[0], a[1]); return 2;
        case FeatureType::Point:
            for (int k = 0; k < 3; ++k) a[k] = Vec3d::Unit(k);
            return 3;
    }
    return 0;
}
/// One Jacobian row along a: [a (map) or R^T a (body) ; p x (R^T a)], since for a row vector
/// a^T (-R [p]x) = (p x (R^T a))^T.
void jacobianRow(const Vec3d& p, const Mat3d& R, const Vec3d& a, bool body, double* Jrow) {
    const Vec3d b = R.transpose() * a;
    const Vec3d rot = p.cross(b);
    const Vec3d& tr = body ? b : a;
    Jrow[0] = tr.x(), Jrow[1] = tr.y(), Jrow[2] = tr.z();
    Jrow[3] = rot.x(), Jrow[4] = rot.y(), Jrow[5] = rot.z();
}
}  // namespace

void correspondenceResidual(const Correspondence& c, const Mat3d& R, const Vec3d& t,
                            double* r, double* J) {
    const Vec3d e = R * c.p + t - c.q;
    Vec3d a[3];
    const int d = residualAxes(c, a);
    for (int k = 0; k < d; ++k) {
        // A point's residual is e itself (not a dot with a unit axis: 0 * inf would be NaN).
        r[k] = c.type == FeatureType::Point ? e[k] : a[k].dot(e);
        if (J) jacobianRow(c.p, R, a[k], false, J + 6 * k);
    }
}

int correspondenceBodyJacobian(const Correspondence& c, const Mat3d& R, double* J) {
    // correspondenceResidual's rows with the translation turned into the body, without the
    // residual: the same products, so the same bits.
    Vec3d a[3];
    const int d = residualAxes(c, a);
    for (int k = 0; k < d; ++k) jacobianRow(c.p, R, a[k], true, J + 6 * k);
    return d;
}

double correspondenceError(const Correspondence& c, const SE3d& T) {
    double r[3];
    correspondenceResidual(c, T.linear(), T.translation(), r, nullptr);
    const int d = residualDim(c.type);
    double s = 0;
    for (int k = 0; k < d; ++k) s += r[k] * r[k];
    return std::sqrt(s);
}

ScanFactor::ScanFactor(std::vector<Correspondence> corr, double sigma)
    : corr_(std::move(corr)), inv_sigma_(1.0 / sigma) {
    int n = 0;
    sqrt_w_.resize(corr_.size());
    for (size_t i = 0; i < corr_.size(); ++i) {
        n += residualDim(corr_[i].type);
        sqrt_w_[i] = std::sqrt(std::max(0.0, corr_[i].weight));
    }
    set_num_residuals(n);
    mutable_parameter_block_sizes()->push_back(7);
}

void ScanFactor::setRobustWeights(const SE3d& T, RobustKernel kernel, double scale) {
    for (size_t i = 0; i < corr_.size(); ++i) {
        const double w = std::max(0.0, corr_[i].weight) *
                         robustWeight(kernel, correspondenceError(corr_[i], T), scale);
        sqrt_w_[i] = std::sqrt(w);
    }
    sums_ = false;
}

bool ScanFactor::Evaluate(double const* const* parameters, double* residuals,
                          double** jacobians) const {
    const double* x = parameters[0];
    const Eigen::Quaterniond q(x[6], x[3], x[4], x[5]);
    const Mat3d R = q.normalized().toRotationMatrix();
    const Vec3d t(x[0], x[1], x[2]);
    double* J = (jacobians && jacobians[0]) ? jacobians[0] : nullptr;
    // Ambient Jacobian of the rotation part: J_theta (1x3) * 2 M(q)^T (3x4), see PoseManifold.
    const Eigen::Matrix<double, 3, 4> twoMt = rotationTangentToAmbient(x + 3);
    int row = 0;
    double r[3], Jt[18];
    for (size_t i = 0; i < corr_.size(); ++i) {
        const Correspondence& c = corr_[i];
        const int d = residualDim(c.type);
        correspondenceResidual(c, R, t, r, J ? Jt : nullptr);
        const double s = sqrt_w_[i] * inv_sigma_;
        for (int k = 0; k < d; ++k) {
            residuals[row + k] = s * r[k];
            if (!J) continue;
            double* Jrow = J + 7 * (row + k);
            const double* g = Jt + 6 * k;
            Jrow[0] = s * g[0], Jrow[1] = s * g[1], Jrow[2] = s * g[2];
            const Eigen::Map<const Eigen::RowVector3d> gth(g + 3);
            Eigen::Map<Eigen::RowVector4d>(Jrow + 3) = s * gth * twoMt;
        }
        row += d;
    }
    return true;
}

Eigen::Matrix<double, 13, 1> ScanFactor::zOf(const Mat3d& R, const Vec3d& t) const {
    Eigen::Matrix<double, 13, 1> z;
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) z[3 * j + k] = R(j, k);
    z.segment<3>(9) = R * p0_ + t - q0_;
    z[12] = 1.0;
    return z;
}

void ScanFactor::sum(const double* x) const {
    const Eigen::Quaterniond q(x[6], x[3], x[4], x[5]);
    const Mat3d R = q.normalized().toRotationMatrix();
    const Vec3d t(x[0], x[1], x[2]);
    p0_.setZero();
    q0_.setZero();
    for (const Correspondence& c : corr_) p0_ += c.p, q0_ += c.q;
    if (!corr_.empty()) p0_ /= static_cast<double>(corr_.size()), q0_ /= static_cast<double>(corr_.size());
    // Each weighted residual's row c (residual s a^T (R p + t - q) = c . z), the residual itself
    // computed directly (its few centimetres are not the difference of the row's metres).
    // The rows in a buffer kept by the thread (one of 2000 correspondences is 200 kB: allocated
    // anew each round, every page of it faulted in again).
    thread_local std::vector<double> buffer;
    const Eigen::Index n = num_residuals();
    if (buffer.size() < static_cast<size_t>(14 * n)) buffer.resize(static_cast<size_t>(14 * n));
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 13>> C(buffer.data(), n, 13);
    Eigen::Map<Eigen::VectorXd> r0(buffer.data() + 13 * n, n);
    Eigen::Index row = 0;
    double r[3];
    Vec3d a[3];
    for (size_t i = 0; i < corr_.size(); ++i) {
        const Correspondence& c = corr_[i];
        const int d = residualAxes(c, a);
        correspondenceResidual(c, R, t, r, nullptr);
        const double s = sqrt_w_[i] * inv_sigma_;
        const Vec3d p = c.p - p0_;
        for (int k = 0; k < d; ++k, ++row) {
            for (int j = 0; j < 3; ++j)
                for (int m = 0; m < 3; ++m) C(row, 3 * j + m) = s * a[k][j] * p[m];
            C.row(row).segment<3>(9) = s * a[k].transpose();
            C(row, 12) = -s * a[k].dot(c.q - q0_);
            r0[row] = s * r[k];
        }
    }
    S_.setZero();
    S_.selfadjointView<Eigen::Lower>().rankUpdate(C.transpose());
    S_ = S_.selfadjointView<Eigen::Lower>();
    b_.noalias() = C.transpose() * r0;
    cost0_ = 0.5 * r0.squaredNorm();
    z0_ = zOf(R, t);
    sums_ = true;
}

double ScanFactor::linearize(const double* x, Mat6d* H, Vec6d* g) const {
    if (!sums_) sum(x);
    const Eigen::Quaterniond q(x[6], x[3], x[4], x[5]);
    const Mat3d R = q.normalized().toRotationMatrix();
    const Vec3d t(x[0], x[1], x[2]);
    const Eigen::Matrix<double, 13, 1> dz = zOf(R, t) - z0_;
    const Eigen::Matrix<double, 13, 1> Sdz = S_ * dz;
    const double cost = cost0_ + dz.dot(b_) + 0.5 * dz.dot(Sdz);
    if (!(H && g)) return cost;
    // D = dz / d[dt, dtheta]: vec(R Exp(dtheta)) moves by vec(R [e_m]x) per unit theta_m;
    // R p0 + t - q0 by dt, and by R (e_m x p0) per unit theta_m.
    Eigen::Matrix<double, 13, 6> D = Eigen::Matrix<double, 13, 6>::Zero();
    for (int m = 0; m < 3; ++m) {
        const Mat3d RE = R * skew(Vec3d::Unit(m));
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) D(3 * j + k, 3 + m) = RE(j, k);
        D.block<3, 1>(9, 3 + m) = RE * p0_;
    }
    D.block<3, 3>(9, 0).setIdentity();
    *g = D.transpose() * (b_ + Sdz);
    *H = D.transpose() * S_ * D;
    *H = 0.5 * (*H + H->transpose());
    return cost;
}

}  // namespace superloc::fusion
