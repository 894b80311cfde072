// SO(3)/SE(3) helpers on Eigen types (pure functions, no state).
#pragma once

#include <superloc/core/types.h>

#include <cmath>

namespace superloc {

/// Radians per degree (INI angles are in degrees).
inline constexpr double kDeg = M_PI / 180.0;

/// Skew-symmetric matrix [v]x such that [v]x w = v x w.
Mat3d skew(const Vec3d& v);

/// SO(3) exponential map (Rodrigues), exact near zero.
Mat3d expSO3(const Vec3d& phi);
/// SO(3) logarithm: rotation vector of R, |phi| <= pi.
Vec3d logSO3(const Mat3d& R);
/// Right Jacobian of SO(3) and its inverse (Forster et al. 2015, eq. 8).
Mat3d rightJacobianSO3(const Vec3d& phi);
Mat3d rightJacobianInvSO3(const Vec3d& phi);

/// SE(3) as (rotation vector, translation) 6-vector, translation first: [t; phi].
/// This is *not* the SE(3) Lie log; it is the decoupled minimal parametrisation used for
/// pose errors and priors throughout SuperLoc.
Vec6d toVec6(const SE3d& T);
SE3d fromVec6(const Vec6d& v);

/// Pose from translation and (x, y, z, w) quaternion components; the quaternion is normalised.
SE3d makePose(double x, double y, double z, double qx, double qy, double qz, double qw);
/// T turned by `yaw` [rad] about the frame's vertical (z) axis through T's origin: the
/// rotation becomes Rz(yaw) R, the translation is kept (a yaw hypothesis of a pose).
SE3d turnedAboutVertical(const SE3d& T, double yaw);
/// Pose from translation and roll/pitch/yaw [rad] (R = Rz(yaw) Ry(pitch) Rx(roll)).
SE3d makePoseRPY(double x, double y, double z, double roll, double pitch, double yaw);

/// Interpolates between two poses: translation linearly, rotation by slerp; s in [0, 1].
SE3d interpolate(const SE3d& a, const SE3d& b, double s);

/// Pose of a time-sorted trajectory at time t (linear/slerp interpolation). Returns nullopt
/// when t lies outside [front.t - tol, back.t + tol] or a gap between the two bracketing
/// samples is longer than max_gap seconds.
std::optional<SE3d> interpolateAt(
    const Trajectory& traj, double t, double max_gap = 1e9, double tol = 1e-6);

/// Translation distance [m] and rotation angle [rad] between two poses.
double translationDistance(const SE3d& a, const SE3d& b);
double rotationAngle(const SE3d& a, const SE3d& b);

/// Makes the rotation part exactly orthonormal (after accumulated products).
SE3d orthonormalize(const SE3d& T);

}  // namespace superloc
