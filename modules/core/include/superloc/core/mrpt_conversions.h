// Conversions between MRPT pose/point types and the Eigen types of superloc/core/types.h.
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <superloc/core/types.h>

namespace superloc {

SE3d toEigen(const mrpt::poses::CPose3D& p);
mrpt::poses::CPose3D toMrpt(const SE3d& T);

/// MRPT orders 6-DoF covariances (x y z yaw pitch roll); SuperLoc uses (x y z roll pitch yaw).
Mat6d covFromMrpt(const mrpt::math::CMatrixDouble66& cov_xyzypr);
mrpt::math::CMatrixDouble66 covToMrpt(const Mat6d& cov_xyzrpy);

}  // namespace superloc
