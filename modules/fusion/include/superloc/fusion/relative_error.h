// The 6-vector error between two poses shared by the pose factors: r = toVec6(A^-1 B),
// (translation, then rotation vector), templated for Ceres autodiff.
#pragma once

#include <ceres/rotation.h>
#include <superloc/core/types.h>

namespace superloc::fusion {

namespace detail {
/// r = toVec6(A^-1 B) for poses A (given as t, q) and B, templated for autodiff.
template <typename T>
void relativeError(const Eigen::Matrix<T, 3, 1>& ta, const Eigen::Quaternion<T>& qa,
                   const Eigen::Matrix<T, 3, 1>& tb, const Eigen::Quaternion<T>& qb, T* r) {
    const Eigen::Quaternion<T> qai = qa.conjugate();
    const Eigen::Matrix<T, 3, 1> dt = qai * (tb - ta);
    const Eigen::Quaternion<T> dq = qai * qb;
    T wxyz[4] = {dq.w(), dq.x(), dq.y(), dq.z()};
    r[0] = dt[0], r[1] = dt[1], r[2] = dt[2];
    ceres::QuaternionToAngleAxis(wxyz, r + 3);
}
}  // namespace detail


}  // namespace superloc::fusion
