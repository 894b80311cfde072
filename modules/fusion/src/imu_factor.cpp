#include <superloc/core/se3.h>
#include <superloc/fusion/imu_factor.h>
#include <superloc/fusion/pose_manifold.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <memory>

namespace superloc::fusion {

ImuFactor::ImuFactor(const imu::Preintegration& pre, const Vec3d& g_map, double acc_bias_rw,
                     double gyro_bias_rw)
    : pre_(pre), g_(g_map), dR_q_(pre.deltaR()) {
    dR_q_.normalize();
    Mat15d cov = Mat15d::Zero();
    cov.block<9, 9>(0, 0) = pre.covariance();
    const double dt = std::max(pre.dt(), 1e-3);
    cov.block<3, 3>(9, 9) = Mat3d::Identity() * acc_bias_rw * acc_bias_rw * dt;
    cov.block<3, 3>(12, 12) = Mat3d::Identity() * gyro_bias_rw * gyro_bias_rw * dt;
    // Floor: a very short interval must not give an unbounded information.
    cov += Mat15d::Identity() * 1e-10;
    const Mat15d info = cov.inverse();
    // sqrt_info^T sqrt_info = info.
    sqrt_info_ = Eigen::LLT<Mat15d>(info).matrixL().transpose();
}

namespace {
/// ImuFactor with its Jacobians written out (Forster et al. 2015, appendix) instead of
/// differentiated with 32-dimensional dual numbers: the same residual (ImuFactor::operator()),
/// the Jacobians in the tangent of each block (translation in the map frame and a right
/// rotation increment for a pose; the speed-bias block as it is), a pose's turned into its 7
/// ambient columns as ScanFactor does (rotation columns times 2 M(q)^T: times PoseManifold's
/// PlusJacobian they give the tangent ones). Test ImuFactor.AnalyticJacobiansAreTheAutodiffOnes.
class AnalyticImuFactor : public ceres::SizedCostFunction<15, 7, 9, 7, 9> {
   public:
    explicit AnalyticImuFactor(const ImuFactor& f) : f_(f) {}
    bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
        f_(x[0], x[1], x[2], x[3], residuals);
        if (!jacobians) return true;
        using Mat = Eigen::Matrix<double, 15, Eigen::Dynamic>;
        const imu::Preintegration& pre = f_.pre_;
        const Eigen::Quaterniond qi(x[0][6], x[0][3], x[0][4], x[0][5]), qj(x[2][6], x[2][3], x[2][4], x[2][5]);
        const Mat3d Ri = qi.toRotationMatrix(), Rj = qj.toRotationMatrix(), RiT = Ri.transpose();
        const Vec3d pi(x[0][0], x[0][1], x[0][2]), pj(x[2][0], x[2][1], x[2][2]);
        const Vec3d vi(x[1][0], x[1][1], x[1][2]), vj(x[3][0], x[3][1], x[3][2]);
        const Vec3d dbg = Vec3d(x[1][6], x[1][7], x[1][8]) - pre.biasLin().gyro;
        const double dt = pre.dt();
        const Vec3d& g = f_.g_;
        // The rotation residual rR = Log(E), E = (dR Exp(phi))^T Ri^T Rj, phi = dR/dbg dbg.
        const Vec3d phi = pre.dR_dbg() * dbg;
        const Mat3d dRc = pre.deltaR() * expSO3(phi);
        const Mat3d E = dRc.transpose() * RiT * Rj;
        const Vec3d rR = logSO3(E);
        const Mat3d JrInv = rightJacobianInvSO3(rR);
        const Vec3d w = vj - vi - g * dt;
        const Vec3d u = pj - pi - vi * dt - 0.5 * g * dt * dt;
        // Unweighted tangent Jacobians; rows: rotation, velocity, position, acc bias, gyro bias.
        Mat Ji = Mat::Zero(15, 6), Jsi = Mat::Zero(15, 9), Jj = Mat::Zero(15, 6), Jsj = Mat::Zero(15, 9);
        Ji.block<3, 3>(0, 3) = -JrInv * Rj.transpose() * Ri;
        Ji.block<3, 3>(3, 3) = skew(RiT * w);
        Ji.block<3, 3>(6, 0) = -RiT;
        Ji.block<3, 3>(6, 3) = skew(RiT * u);
        Jsi.block<3, 3>(0, 6) = -JrInv * E.transpose() * rightJacobianSO3(phi) * pre.dR_dbg();
        Jsi.block<3, 3>(3, 0) = -RiT;
        Jsi.block<3, 3>(3, 3) = -pre.dv_dba();
        Jsi.block<3, 3>(3, 6) = -pre.dv_dbg();
        Jsi.block<3, 3>(6, 0) = -RiT * dt;
        Jsi.block<3, 3>(6, 3) = -pre.dp_dba();
        Jsi.block<3, 3>(6, 6) = -pre.dp_dbg();
        Jsi.block<6, 6>(9, 3) = -Eigen::Matrix<double, 6, 6>::Identity();
        Jj.block<3, 3>(0, 3) = JrInv;
        Jj.block<3, 3>(6, 0) = RiT;
        Jsj.block<3, 3>(3, 0) = RiT;
        Jsj.block<6, 6>(9, 3) = Eigen::Matrix<double, 6, 6>::Identity();
        const auto pose = [&](const Mat& Jt, const double* xp, double* out) {
            const Mat W = f_.sqrt_info_ * Jt;
            Eigen::Map<Eigen::Matrix<double, 15, 7, Eigen::RowMajor>> J(out);
            J.leftCols<3>() = W.leftCols<3>();
            J.rightCols<4>() = W.rightCols<3>() * rotationTangentToAmbient(xp + 3);
        };
        const auto speedBias = [&](const Mat& Jt, double* out) {
            Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>> J(out);
            J = f_.sqrt_info_ * Jt;
        };
        if (jacobians[0]) pose(Ji, x[0], jacobians[0]);
        if (jacobians[1]) speedBias(Jsi, jacobians[1]);
        if (jacobians[2]) pose(Jj, x[2], jacobians[2]);
        if (jacobians[3]) speedBias(Jsj, jacobians[3]);
        return true;
    }

   private:
    ImuFactor f_;
};
}  // namespace

ceres::CostFunction* ImuFactor::Create(const imu::Preintegration& pre, const Vec3d& g_map,
                                       double acc_bias_rw, double gyro_bias_rw) {
    return new AnalyticImuFactor(ImuFactor(pre, g_map, acc_bias_rw, gyro_bias_rw));
}

ceres::CostFunction* ImuFactor::CreateAutoDiff(const imu::Preintegration& pre, const Vec3d& g_map,
                                               double acc_bias_rw, double gyro_bias_rw) {
    return new ceres::AutoDiffCostFunction<ImuFactor, 15, 7, 9, 7, 9>(
        new ImuFactor(pre, g_map, acc_bias_rw, gyro_bias_rw));
}

}  // namespace superloc::fusion
