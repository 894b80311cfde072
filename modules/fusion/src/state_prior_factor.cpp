// StatePriorFactor's Jacobians written out (state_prior_factor.h).
#include <superloc/core/se3.h>
#include <superloc/fusion/pose_manifold.h>
#include <superloc/fusion/state_prior_factor.h>

#include <ceres/sized_cost_function.h>

namespace superloc::fusion {

namespace {
/// r = L e, e = [R_ref^T (t - t_ref); Log(R_ref^T R); sb - sb_ref]. In the pose's tangent
/// (translation in the map frame, a right rotation increment) de/dt = R_ref^T and
/// de/dtheta = Jr^-1(Log(R_ref^T R)); the speed-bias block's is the identity. The pose's
/// rotation columns are turned into its 4 ambient quaternion columns as the other analytic
/// factors do (times 2 M(q)^T: PoseManifold's PlusJacobian maps them back exactly).
class AnalyticStatePriorFactor : public ceres::SizedCostFunction<15, 7, 9> {
   public:
    explicit AnalyticStatePriorFactor(const StatePrior& p) : f_(p) {}
    bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
        f_(x[0], x[1], residuals);
        if (!jacobians) return true;
        const StatePrior& p = f_.p_;
        if (jacobians[0]) {
            const Eigen::Quaterniond q(x[0][6], x[0][3], x[0][4], x[0][5]), dq = f_.qr_.conjugate() * q;
            double wxyz[4] = {dq.w(), dq.x(), dq.y(), dq.z()}, phi[3];
            ceres::QuaternionToAngleAxis(wxyz, phi);
            Eigen::Matrix<double, 15, 6> W;
            W.leftCols<3>() = p.sqrt_info.leftCols<3>() * p.T_ref.linear().transpose();
            W.rightCols<3>() = p.sqrt_info.middleCols<3>(3) * rightJacobianInvSO3(Vec3d(phi[0], phi[1], phi[2]));
            Eigen::Map<Eigen::Matrix<double, 15, 7, Eigen::RowMajor>> J(jacobians[0]);
            J.leftCols<3>() = W.leftCols<3>();
            J.rightCols<4>() = W.rightCols<3>() * rotationTangentToAmbient(x[0] + 3);
        }
        if (jacobians[1]) {
            Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>> S(jacobians[1]);
            S = p.sqrt_info.rightCols<9>();
        }
        return true;
    }

   private:
    StatePriorFactor f_;
};
}  // namespace

ceres::CostFunction* StatePriorFactor::Create(const StatePrior& p) { return new AnalyticStatePriorFactor(p); }

}  // namespace superloc::fusion
