// Scan-to-map residuals (paper eq. 1 and the point/line/plane terms of eq. 12).
//
// For a scan point p (body = IMU frame) and the body pose T_map_imu = (R, t), x = R p + t:
//   plane:  r = n . (x - q)                        (1 residual, n unit normal)
//   line:   r = [e1 . (x - q), e2 . (x - q)]       (2 residuals, e1, e2 ⊥ line direction d)
//   point:  r = x - q                              (3 residuals)
// each multiplied by sqrt(fit weight * robust weight) / sigma. With the right increment of
// PoseManifold, dx/d dt = I and dx/d dtheta = -R [p]x.
//
// All correspondences of a scan form ONE Ceres residual block with analytic Jacobians (the
// per-correspondence blocks of Ceres cost about ten times more per iteration). The robust
// kernel is applied as iteratively re-weighted least squares: the weights are computed from the
// residuals at the pose where the correspondences were made (setRobustWeights), held during a
// solve and recomputed at every re-association.
#pragma once

#include <ceres/cost_function.h>
#include <superloc/core/types.h>
#include <superloc/core/correspondence.h>

#include <string>
#include <vector>

namespace superloc::fusion {

enum class RobustKernel { None, Huber, Cauchy };
/// "none", "huber", "cauchy"; throws std::invalid_argument on anything else.
RobustKernel robustKernelFromString(const std::string& s);
/// IRLS weight rho'(r^2) of a residual of norm r for a kernel of scale k.
double robustWeight(RobustKernel kernel, double r, double k);

/// Number of scalar residuals of a correspondence (1, 2 or 3).
int residualDim(FeatureType t);
/// Unweighted residual of one correspondence at pose (R, t) into r (residualDim entries) and,
/// when J is not null, its Jacobian w.r.t. [dt, dtheta] (row-major, residualDim x 6).
void correspondenceResidual(const Correspondence& c, const Mat3d& R, const Vec3d& t,
                            double* r, double* J);
/// The Jacobian of correspondenceResidual w.r.t. a body perturbation [dt (body), dtheta] (its
/// translation rows turned by R^T), without the residual, into J (row-major, residualDim x 6);
/// returns residualDim.
int correspondenceBodyJacobian(const Correspondence& c, const Mat3d& R, double* J);
/// Norm of the unweighted residual (point-to-plane distance etc.).
double correspondenceError(const Correspondence& c, const SE3d& T_map_imu);

class ScanFactor : public ceres::CostFunction {
   public:
    /// sigma [m]: measurement standard deviation the residuals are divided by.
    ScanFactor(std::vector<Correspondence> corr, double sigma);

    /// IRLS: per-correspondence weight = fit weight * rho'(|r|) at T_map_imu.
    void setRobustWeights(const SE3d& T_map_imu, RobustKernel kernel, double scale);
    const std::vector<Correspondence>& correspondences() const { return corr_; }
    const std::vector<double>& sqrtWeights() const { return sqrt_w_; }
    /// Hands the correspondences back (the factor is empty afterwards).
    std::vector<Correspondence> release() {
        sqrt_w_.clear();
        sums_ = false;
        return std::move(corr_);
    }

    bool Evaluate(double const* const* parameters, double* residuals,
                  double** jacobians) const override;

    /// Cost 0.5 * sum of the squared weighted residuals at pose x (Ceres' 7-vector: t, then
    /// the quaternion x y z w) and, when H and g are not null, the normal equations in the
    /// pose manifold's tangent [dt, dtheta]: H = J^T J, g = J^T r. Each residual is linear in
    /// z = [vec(R), R p0 + t - q0, 1] (p0, q0: the correspondences' centroids), r_i = c_i . z, so
    /// the first call after the weights are set sums S = sum c_i c_i^T (13 x 13), b = S z0 and
    /// the cost at its pose x0 in one pass over the correspondences; every call then costs the
    /// same whatever their number: cost(x) = cost0 + dz^T b + dz^T S dz / 2 (dz = z - z0, so no
    /// large terms cancel), g = D^T (b + S dz), H = D^T S D with D = dz/d(tangent). Equal to
    /// the sums over the residuals to rounding (test ScanFactor.LinearizeFromItsSumsIsTheDirectSum).
    /// Not for concurrent calls on one factor (the sums are the factor's scratch).
    double linearize(const double* x, Mat6d* H, Vec6d* g) const;

   private:
    std::vector<Correspondence> corr_;
    std::vector<double> sqrt_w_;
    double inv_sigma_;
    // linearize's sums (valid while sums_): S = sum c c^T, b = S z0, the cost at z0, centroids.
    mutable bool sums_ = false;
    mutable Eigen::Matrix<double, 13, 13> S_;
    mutable Eigen::Matrix<double, 13, 1> b_, z0_;
    mutable double cost0_ = 0;
    mutable Vec3d p0_, q0_;
    void sum(const double* x) const;
    Eigen::Matrix<double, 13, 1> zOf(const Mat3d& R, const Vec3d& t) const;
};

}  // namespace superloc::fusion
