// Manifold of a pose block [t (3), q (4, Eigen x y z w)] with a right (body-frame) rotation
// increment and a map-frame translation increment:
//   Plus([t, q], [dt, dtheta]) = [t + dt, q ⊗ Exp(dtheta)]
// The tangent order [dt, dtheta] matches SuperLoc's (x y z roll pitch yaw) 6-vectors.
#pragma once

#include <ceres/manifold.h>

#include <Eigen/Core>

namespace superloc::fusion {

class PoseManifold : public ceres::Manifold {
   public:
    int AmbientSize() const override { return 7; }
    int TangentSize() const override { return 6; }
    bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
    bool PlusJacobian(const double* x, double* jacobian) const override;
    bool Minus(const double* y, const double* x, double* y_minus_x) const override;
    bool MinusJacobian(const double* x, double* jacobian) const override;
};

/// The 4x3 matrix M(q) with d(q ⊗ Exp(dtheta))/d dtheta = M(q) / 2 at dtheta = 0 (Eigen order
/// x y z w). Its columns are orthonormal, so 2 M^T maps a rotation-tangent Jacobian to an
/// ambient one that PlusJacobian maps back exactly (used by analytic cost functions).
void quaternionRightMatrix(const double* q_xyzw, double* M_row_major_4x3);
/// 2 M(q)^T (3 x 4): a pose block's rotation-tangent Jacobian columns times this are its 4
/// ambient quaternion columns, which PlusJacobian maps back exactly (the analytic cost
/// functions: ScanFactor, the condensed scan, the IMU factor).
Eigen::Matrix<double, 3, 4> rotationTangentToAmbient(const double* q_xyzw);

}  // namespace superloc::fusion
