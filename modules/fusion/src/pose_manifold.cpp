#include <superloc/core/se3.h>
#include <superloc/fusion/pose_manifold.h>

#include <Eigen/Geometry>

namespace superloc::fusion {

namespace {
using Quat = Eigen::Quaterniond;
Quat quatOf(const double* x) { return Quat(x[6], x[3], x[4], x[5]); }
}  // namespace

bool PoseManifold::Plus(const double* x, const double* delta, double* out) const {
    for (int k = 0; k < 3; ++k) out[k] = x[k] + delta[k];
    const Vec3d phi(delta[3], delta[4], delta[5]);
    const Quat q = (quatOf(x) * Quat(expSO3(phi))).normalized();
    out[3] = q.x();
    out[4] = q.y();
    out[5] = q.z();
    out[6] = q.w();
    return true;
}

void quaternionRightMatrix(const double* q, double* M) {
    // q ⊗ (v, 0) for q = (qv, w): vector part w v + qv x v, scalar part -qv . v.
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double m[12] = {w, -z, y,   //
                          z, w,  -x,  //
                          -y, x, w,   //
                          -x, -y, -z};
    for (int k = 0; k < 12; ++k) M[k] = m[k];
}

Eigen::Matrix<double, 3, 4> rotationTangentToAmbient(const double* q) {
    double M[12];
    quaternionRightMatrix(q, M);
    return 2.0 * Eigen::Map<Eigen::Matrix<double, 4, 3, Eigen::RowMajor>>(M).transpose();
}

bool PoseManifold::PlusJacobian(const double* x, double* jac) const {
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jac);
    J.setZero();
    J.block<3, 3>(0, 0).setIdentity();
    double M[12];
    quaternionRightMatrix(x + 3, M);
    J.block<4, 3>(3, 3) = 0.5 * Eigen::Map<Eigen::Matrix<double, 4, 3, Eigen::RowMajor>>(M);
    return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* out) const {
    for (int k = 0; k < 3; ++k) out[k] = y[k] - x[k];
    const Vec3d phi = logSO3((quatOf(x).conjugate() * quatOf(y)).toRotationMatrix());
    for (int k = 0; k < 3; ++k) out[3 + k] = phi[k];
    return true;
}

bool PoseManifold::MinusJacobian(const double* x, double* jac) const {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jac);
    J.setZero();
    J.block<3, 3>(0, 0).setIdentity();
    double M[12];
    quaternionRightMatrix(x + 3, M);
    J.block<3, 4>(3, 3) = 2.0 * Eigen::Map<Eigen::Matrix<double, 4, 3, Eigen::RowMajor>>(M).transpose();
    return true;
}

}  // namespace superloc::fusion
