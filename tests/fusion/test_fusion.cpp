#include <gtest/gtest.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/fusion/frame_problem.h>
#include <superloc/fusion/imu_factor.h>
#include <superloc/fusion/pose_prior_factor.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/fusion/relative_pose_factor.h>
#include <superloc/fusion/pose_manifold.h>
#include <superloc/fusion/scan_factor.h>
#include <superloc/fusion/state_prior_factor.h>

#include <ceres/ceres.h>

#include <memory>
#include <random>

using namespace superloc;
using namespace superloc::fusion;

namespace {
// Box room 20 x 12 x 4 m with a pole (line) and a few isolated points; scan points seen from
// the body pose T_true, correspondences with exact map geometry.
std::vector<Correspondence> boxRoom(const SE3d& T_true, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Correspondence> out;
    struct Plane { Vec3d n; double d; };  // n . x = d
    const Plane planes[6] = {{Vec3d::UnitX(), -10}, {Vec3d::UnitX(), 10}, {Vec3d::UnitY(), -6},
                             {Vec3d::UnitY(), 6},   {Vec3d::UnitZ(), 0},  {Vec3d::UnitZ(), 4}};
    for (int i = 0; i < n; ++i) {
        Correspondence c;
        const int kind = i % 10;
        Vec3d x_map;
        if (kind < 8) {
            const Plane& P = planes[i % 6];
            x_map = Vec3d(-10 + 20 * u(rng), -6 + 12 * u(rng), 4 * u(rng));
            x_map += (P.d - P.n.dot(x_map)) * P.n;  // onto the plane
            c.type = FeatureType::Plane;
            c.n = P.n;
            c.q = x_map + 0.3 * (Vec3d::Ones() - P.n);  // another point of the plane
        } else if (kind == 8) {
            x_map = Vec3d(3, 2, 4 * u(rng));  // vertical pole at (3, 2)
            c.type = FeatureType::Line;
            c.n = Vec3d::UnitZ();
            c.q = Vec3d(3, 2, 1);
        } else {
            x_map = Vec3d(-10 + 20 * u(rng), -6 + 12 * u(rng), 4 * u(rng));
            c.type = FeatureType::Point;
            c.q = x_map;
        }
        c.p = T_true.inverse() * x_map;
        out.push_back(c);
    }
    return out;
}

// The factor's residuals at the pose of s and their Jacobian in the manifold's 6-D tangent
// (Ceres' ambient 7-column Jacobian times PlusJacobian).
Eigen::MatrixXd tangentJacobian(const ScanFactor& f, const FrameState& s, std::vector<double>& r) {
    const int nr = f.num_residuals();
    std::vector<double> J(static_cast<size_t>(nr) * 7);
    r.assign(static_cast<size_t>(nr), 0.0);
    const double* params[1] = {s.pose};
    double* jac[1] = {J.data()};
    EXPECT_TRUE(f.Evaluate(params, r.data(), jac));
    PoseManifold m;
    double P[42];
    m.PlusJacobian(s.pose, P);
    return Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 7, Eigen::RowMajor>>(J.data(), nr, 7) *
           Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>>(P);
}
}  // namespace

TEST(PoseManifold, PlusMinusAndJacobian) {
    PoseManifold m;
    FrameState s;
    s.setPose(makePoseRPY(1, 2, 3, 0.3, -0.2, 1.1));
    const double d[6] = {0.1, -0.2, 0.05, 0.02, -0.03, 0.04};
    double y[7], back[6];
    m.Plus(s.pose, d, y);
    m.Minus(y, s.pose, back);
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(back[k], d[k], 1e-12);
    // Plus is a right increment: rotation of y = R Exp(dtheta).
    FrameState sy;
    std::copy(y, y + 7, sy.pose);
    const Mat3d expect = s.T_map_imu().linear() * expSO3(Vec3d(d[3], d[4], d[5]));
    EXPECT_LT((sy.T_map_imu().linear() - expect).norm(), 1e-12);
}

TEST(ScanFactor, AnalyticJacobianMatchesNumeric) {
    const SE3d T = makePoseRPY(0.5, -0.3, 0.2, 0.05, -0.1, 0.7);
    auto corr = boxRoom(makePoseRPY(0, 0, 0.1, 0, 0, 0.6), 40, 3);
    ScanFactor f(corr, 0.05);
    FrameState s;
    s.setPose(T);
    const int nr = f.num_residuals();
    std::vector<double> r0, r1(nr);
    const Eigen::MatrixXd Jt = tangentJacobian(f, s, r0);
    PoseManifold m;
    const double h = 1e-7;
    for (int k = 0; k < 6; ++k) {
        double d[6] = {0, 0, 0, 0, 0, 0}, y[7];
        d[k] = h;
        m.Plus(s.pose, d, y);
        const double* py[1] = {y};
        f.Evaluate(py, r1.data(), nullptr);
        for (int i = 0; i < nr; ++i) EXPECT_NEAR((r1[i] - r0[i]) / h, Jt(i, k), 1e-4) << i << "," << k;
    }
}

TEST(FrameProblem, ScanOnlyRecoversPoseFromPerturbation) {
    const SE3d T_true = makePoseRPY(1.0, -0.5, 0.3, 0.02, -0.01, 0.4);
    ScanFactor scan(boxRoom(T_true, 600, 5), 0.05);
    FrameState prev, cur;
    cur.setPose(T_true * makePoseRPY(0.3, -0.2, 0.1, 0.02, 0.03, -0.08));
    FrameProblemInputs in;
    in.prev = &prev;
    in.cur = &cur;
    in.scan = &scan;
    FusionParams p;
    p.max_iterations = 30;
    const auto s = solveFrame(in, p);
    EXPECT_TRUE(s.usable);
    EXPECT_LT(translationDistance(cur.T_map_imu(), T_true), 1e-6);
    EXPECT_LT(rotationAngle(cur.T_map_imu(), T_true), 1e-6);
    EXPECT_LT(s.final_cost, 1e-10);
}

namespace {
// The scan-only problem solved by Ceres as solveFrame did before it had its own solver.
/// Ceres on the scan's N x 7 block itself (and odom_alt's relative prior from `prev`, held
/// constant, when given): what solveFrame's condensed scan block must reproduce.
SolveSummary solveWithCeres(ScanFactor& scan, FrameState& cur, int max_iterations,
                            const RelativePosePrior* prior = nullptr, FrameState* prev = nullptr) {
    struct NonOwning : ceres::CostFunction {
        explicit NonOwning(const ceres::CostFunction* f) : f_(f) {
            set_num_residuals(f->num_residuals());
            *mutable_parameter_block_sizes() = f->parameter_block_sizes();
        }
        bool Evaluate(double const* const* p, double* r, double** J) const override { return f_->Evaluate(p, r, J); }
        const ceres::CostFunction* f_;
    };
    static PoseManifold manifold;
    ceres::Problem::Options popt;
    popt.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(popt);
    problem.AddParameterBlock(cur.pose, 7, &manifold);
    problem.AddResidualBlock(new NonOwning(&scan), nullptr, cur.pose);
    if (prior) {
        problem.AddParameterBlock(prev->pose, 7, &manifold);
        problem.AddResidualBlock(RelativePoseFactor::Create(prior->delta, prior->sqrt_info), nullptr, prev->pose,
                                 cur.pose);
        problem.SetParameterBlockConstant(prev->pose);
    }
    ceres::Solver::Options opt;
    opt.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    opt.max_num_iterations = max_iterations;
    opt.num_threads = 1;
    opt.logging_type = ceres::SILENT;
    opt.function_tolerance = 1e-8;
    opt.parameter_tolerance = 1e-8;
    ceres::Solver::Summary summary;
    ceres::Solve(opt, &problem, &summary);
    SolveSummary out;
    out.usable = summary.IsSolutionUsable();
    out.iterations = static_cast<int>(summary.iterations.size()) - 1;
    out.initial_cost = summary.initial_cost;
    out.final_cost = summary.final_cost;
    Eigen::Map<Eigen::Vector4d>(cur.pose + 3).normalize();
    return out;
}
/// A box room's correspondences seen from T_true (800, seed 11) and the corridor inside it (its
/// planes whose normal is within 60 deg of the y-z plane: x unheld), each feature 3 cm noisy.
std::pair<std::vector<Correspondence>, std::vector<Correspondence>> noisyRoomAndCorridor(const SE3d& T_true) {
    auto room = boxRoom(T_true, 800, 11);
    std::vector<Correspondence> corridor;
    for (const auto& c : room)
        if (c.type == FeatureType::Plane && std::abs(c.n.x()) < 0.5) corridor.push_back(c);
    std::mt19937 rng(4);
    std::normal_distribution<double> N(0, 0.03);
    for (auto* corr : {&room, &corridor})
        for (auto& c : *corr) c.p += Vec3d(N(rng), N(rng), N(rng));
    return {std::move(room), std::move(corridor)};
}
/// solveFrame's solve (sa, ending at a) is Ceres' on the full block (sb, ending at b): usable,
/// the same iterations, costs and pose to 1e-9.
void expectSameSolve(const SolveSummary& sa, const FrameState& a, const SolveSummary& sb, const FrameState& b,
                     int iters) {
    ASSERT_TRUE(sa.usable);
    ASSERT_TRUE(sb.usable);
    EXPECT_EQ(sa.iterations, sb.iterations) << iters;
    EXPECT_NEAR(sa.initial_cost, sb.initial_cost, 1e-9 * sb.initial_cost);
    EXPECT_NEAR(sa.final_cost, sb.final_cost, 1e-9 * sb.initial_cost);
    EXPECT_LT(translationDistance(a.T_map_imu(), b.T_map_imu()), 1e-9) << iters;
    EXPECT_LT(rotationAngle(a.T_map_imu(), b.T_map_imu()), 1e-9) << iters;
}
}  // namespace

TEST(FrameProblem, ScanOnlyMatchesCeres) {
    // solveFrame's own Levenberg-Marquardt for scan-only problems against Ceres on the same
    // factor: noisy scan points (the minimum's cost is not 0), Cauchy IRLS weights at the start,
    // starts near and far (steps rejected), 1 to 8 iterations (the path, not only the minimum).
    const SE3d T_true = makePoseRPY(1.0, -0.5, 0.3, 0.02, -0.01, 0.4);
    auto corr = boxRoom(T_true, 800, 11);
    std::mt19937 rng(4);
    std::normal_distribution<double> N(0, 0.03);
    for (auto& c : corr) c.p += Vec3d(N(rng), N(rng), N(rng));
    const SE3d starts[4] = {T_true * makePoseRPY(0.05, -0.03, 0.02, 0.005, 0.004, -0.01),
                            T_true * makePoseRPY(0.6, -0.4, 0.2, 0.05, 0.06, -0.25),
                            T_true * makePoseRPY(2.5, 1.5, -0.5, 0.2, -0.1, 0.9),
                            T_true * makePoseRPY(4.0, -3.0, 1.0, 0.6, -0.5, 2.2)};
    FusionParams p;
    for (const SE3d& T0 : starts) {
        for (int iters : {1, 2, 8}) {
            ScanFactor scan(corr, 0.05);
            scan.setRobustWeights(T0, RobustKernel::Cauchy, 0.3);
            FrameState prev, a, b;
            a.setPose(T0);
            b.setPose(T0);
            FrameProblemInputs in;
            in.prev = &prev;
            in.cur = &a;
            in.scan = &scan;
            p.max_iterations = iters;
            const auto sa = solveFrame(in, p);
            const auto sb = solveWithCeres(scan, b, iters);
            expectSameSolve(sa, a, sb, b, iters);
        }
    }
    // The linearization is Ceres' J^T J and J^T r in the manifold's tangent.
    ScanFactor scan(corr, 0.05);
    FrameState s;
    s.setPose(starts[1]);
    std::vector<double> r;
    const Eigen::MatrixXd Jl = tangentJacobian(scan, s, r);
    const Eigen::VectorXd rv = Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size()));
    Mat6d H;
    Vec6d g;
    const double cost = scan.linearize(s.pose, &H, &g);
    EXPECT_NEAR(cost, 0.5 * rv.squaredNorm(), 1e-9 * cost);
    EXPECT_LT((H - Jl.transpose() * Jl).norm(), 1e-9 * H.norm());
    EXPECT_LT((g - Jl.transpose() * rv).norm(), 1e-9 * H.norm());
}

TEST(ScanFactor, LinearizeFromItsSumsIsTheDirectSum) {
    // linearize sums the correspondences once, at its first pose, and answers every later pose
    // from those sums: the cost, J^T J and J^T r over the residuals themselves, far from that
    // first pose too, in a map frame hundreds of metres from its origin (KITTI's).
    const SE3d far_away = makePoseRPY(350.0, -120.0, 8.0, 0.0, 0.0, 1.2);
    const SE3d T_true = far_away * makePoseRPY(1.0, -0.5, 0.3, 0.02, -0.01, 0.4);
    auto corr = boxRoom(makePoseRPY(1.0, -0.5, 0.3, 0.02, -0.01, 0.4), 900, 7);
    std::mt19937 rng(9);
    std::normal_distribution<double> N(0, 0.02);
    for (auto& c : corr) {
        c.p += Vec3d(N(rng), N(rng), N(rng));
        c.q = far_away * c.q;
        if (c.type != FeatureType::Point) c.n = far_away.linear() * c.n;
        c.weight = 0.3 + 0.7 * std::abs(N(rng)) / 0.02;
    }
    ScanFactor scan(corr, 0.05);
    scan.setRobustWeights(T_true, RobustKernel::Cauchy, 0.2);
    FrameState first;
    first.setPose(T_true * makePoseRPY(0.02, 0.01, -0.01, 0.001, 0.002, -0.003));
    Mat6d H;
    Vec6d g;
    scan.linearize(first.pose, &H, &g);  // the sums are made here
    for (const SE3d& d : {SE3d(makePoseRPY(0, 0, 0, 0, 0, 0)), SE3d(makePoseRPY(0.6, -0.4, 0.2, 0.05, 0.06, -0.25)),
                          SE3d(makePoseRPY(-3.0, 2.0, 0.5, 0.3, -0.2, 1.5))}) {
        FrameState s;
        s.setPose(T_true * d);
        std::vector<double> r;
        const Eigen::MatrixXd Jl = tangentJacobian(scan, s, r);
        const Eigen::VectorXd rv = Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size()));
        const double cost = scan.linearize(s.pose, &H, &g);
        const Eigen::MatrixXd Hd = Jl.transpose() * Jl;
        const Eigen::VectorXd gd = Jl.transpose() * rv;
        EXPECT_NEAR(cost, 0.5 * rv.squaredNorm(), 1e-10 * cost);
        EXPECT_NEAR(scan.linearize(s.pose, nullptr, nullptr), cost, 1e-12 * cost);
        EXPECT_LT((H - Hd).norm(), 1e-10 * Hd.norm());
        EXPECT_LT((g - gd).norm(), 1e-10 * std::max(gd.norm(), 1e-6 * Hd.norm()));
    }
    // New weights: the sums are made again.
    scan.setRobustWeights(T_true, RobustKernel::Cauchy, 0.05);
    FrameState s;
    s.setPose(T_true);
    std::vector<double> r;
    const Eigen::MatrixXd Jl = tangentJacobian(scan, s, r);
    const Eigen::VectorXd rv = Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size()));
    EXPECT_NEAR(scan.linearize(s.pose, &H, &g), 0.5 * rv.squaredNorm(), 1e-10 * rv.squaredNorm());
    EXPECT_LT((H - Jl.transpose() * Jl).norm(), 1e-10 * H.norm());
}

TEST(FrameProblem, CondensedScanIsTheScanToRounding) {
    // solveFrame gives Ceres the scan's normal equations through 7 residuals (CondensedScan):
    // the same steps as Ceres on the N x 7 block, with odom_alt's prior beside it. A box room,
    // and a corridor whose scan leaves its axis unheld (a singular H: the prior holds x).
    const SE3d T_true = makePoseRPY(1.0, -0.5, 0.3, 0.02, -0.01, 0.4);
    auto [room, corridor] = noisyRoomAndCorridor(T_true);
    FrameState prev;
    prev.setPose(makePoseRPY(0.2, -0.4, 0.3, 0.01, 0.0, 0.35));
    RelativePosePrior prior;
    prior.delta = prev.T_map_imu().inverse() * T_true * makePoseRPY(0.04, 0.01, -0.01, 0.002, 0.001, 0.003);
    prior.sqrt_info = Vec6d(1 / 0.05, 1 / 0.05, 1 / 0.05, 1 / 0.01, 1 / 0.01, 1 / 0.01).asDiagonal();
    FusionParams p;
    p.active.prior_kernel = "none";  // the reference below adds the prior without a loss
    for (const auto* corr : {&room, &corridor})
        for (const SE3d& T0 : {T_true * makePoseRPY(0.05, -0.03, 0.02, 0.005, 0.004, -0.01),
                               T_true * makePoseRPY(0.6, -0.4, 0.2, 0.05, 0.06, -0.25)})
            for (int iters : {1, 3, 10}) {
                ScanFactor scan(*corr, 0.05);
                scan.setRobustWeights(T0, RobustKernel::Cauchy, 0.3);
                FrameState a, b, prev_a = prev, prev_b = prev;
                a.setPose(T0);
                b.setPose(T0);
                FrameProblemInputs in;
                in.prev = &prev_a;
                in.cur = &a;
                in.scan = &scan;
                in.prior = prior;
                p.max_iterations = iters;
                const auto sa = solveFrame(in, p);
                const auto sb = solveWithCeres(scan, b, iters, &prior, &prev_b);
                expectSameSolve(sa, a, sb, b, iters);
                // Far from the start: the solve did something.
                if (iters == 10) {
                    EXPECT_GT(translationDistance(a.T_map_imu(), T0), 0.01);
                }
            }
}

TEST(FrameProblem, WindowSolveMatchesCeres) {
    // solveFrame's own Levenberg-Marquardt on the IMU window (IMU factor, the previous state's
    // prior, odom_alt's relative prior under each robust loss, the scan) and on the no-IMU window
    // (the relative prior, the previous pose held; a pose prior) against Ceres' on the same
    // problem: the same iterations, costs and states to 1e-9, the same marginal. Starts near and
    // far, 1 to 8 iterations; a corridor whose scan leaves its axis to the priors.
    const SE3d T_true = makePoseRPY(1.0, -0.5, 0.3, 0.02, -0.01, 0.4);
    auto [room, corridor] = noisyRoomAndCorridor(T_true);
    imu::Preintegration pre(imu::ImuBias{Vec3d(0.02, -0.01, 0.03), Vec3d(0.002, -0.001, 0.003)},
                            imu::ImuNoise{0.02, 0.002});
    for (int k = 0; k < 20; ++k) pre.integrate(Vec3d(0.4, 0.2, 9.7), Vec3d(0.2, -0.3, 0.5), 0.005);
    FrameState prev0;
    prev0.setPose(T_true * makePoseRPY(-0.12, -0.03, 0.0, 0.0, 0.0, -0.05));
    prev0.setVelocity(Vec3d(1.0, 0.3, 0.0));
    prev0.setBias({Vec3d(0.05, 0.0, -0.02), Vec3d(0.001, 0.002, 0.0)});
    RelativePosePrior rel;
    rel.delta = prev0.T_map_imu().inverse() * T_true * makePoseRPY(0.04, 0.01, -0.01, 0.002, 0.001, 0.003);
    rel.sqrt_info = Vec6d(1 / 0.05, 1 / 0.05, 1 / 0.05, 1 / 0.01, 1 / 0.01, 1 / 0.01).asDiagonal();
    int cases = 0;
    for (const auto* corr : {&room, &corridor})
        for (const char* kernel : {"none", "cauchy", "huber"})
            for (const bool with_imu : {true, false})
                for (const SE3d& T0 : {T_true * makePoseRPY(0.05, -0.03, 0.02, 0.005, 0.004, -0.01),
                                       T_true * makePoseRPY(0.6, -0.4, 0.2, 0.05, 0.06, -0.25)})
                    for (int iters : {1, 3, 8}) {
                        FusionParams p;
                        p.active.prior_kernel = kernel;
                        p.active.prior_kernel_sigmas = 2.0;  // the prior's 4 cm step is 0.8 sigma: both branches of Huber
                        p.max_iterations = iters;
                        ScanFactor scan(*corr, 0.05);
                        scan.setRobustWeights(T0, RobustKernel::Cauchy, 0.3);
                        FrameState pa = prev0, pb = prev0, a, b;
                        for (FrameState* st : {&a, &b}) {
                            st->setPose(T0);
                            st->setVelocity(Vec3d(1.05, 0.3, 0.0));
                            st->setBias(prev0.bias());
                        }
                        FrameProblemInputs ia, ib;
                        ia.prev = &pa, ia.cur = &a;
                        ib.prev = &pb, ib.cur = &b;
                        for (FrameProblemInputs* in : {&ia, &ib}) {
                            in->scan = &scan;
                            in->prior = rel;
                            if (with_imu) {
                                in->setImu(&pre, imu::ImuParams{});
                                in->marginalize = true;
                            } else {
                                in->cur_pose_prior = std::make_pair(T_true, Mat6d(Mat6d::Identity() * 2.0));
                            }
                        }
                        const auto sa = solveFrame(ia, p);
                        const auto sb = solveFrameWithCeres(ib, p);
                        SCOPED_TRACE(std::string(kernel) + (with_imu ? " imu" : " no imu") + " iters " + std::to_string(iters));
                        expectSameSolve(sa, a, sb, b, iters);
                        EXPECT_LT(translationDistance(pa.T_map_imu(), pb.T_map_imu()), 1e-9);
                        EXPECT_LT((a.velocity() - b.velocity()).norm(), 1e-9);
                        EXPECT_LT((pa.velocity() - pb.velocity()).norm(), 1e-9);
                        ASSERT_EQ(sa.marginal.has_value(), sb.marginal.has_value());
                        if (sa.marginal) {
                            const Mat15d Ma = sa.marginal->sqrt_info.transpose() * sa.marginal->sqrt_info;
                            const Mat15d Mb = sb.marginal->sqrt_info.transpose() * sb.marginal->sqrt_info;
                            EXPECT_LT((Ma - Mb).norm(), 1e-7 * Mb.norm());
                        }
                        if (!with_imu) {
                            EXPECT_EQ(pa.T_map_imu().matrix(), prev0.T_map_imu().matrix()) << "held";
                        }
                        ++cases;
                    }
    EXPECT_EQ(cases, 72);
}

TEST(FrameProblem, ImuFactorAloneReproducesPrediction) {
    // Constant acceleration + rotation: the IMU-only problem must land on the prediction.
    imu::Preintegration pre;
    for (int k = 0; k < 100; ++k) pre.integrate(Vec3d(0.5, 0.1, 9.81), Vec3d(0.1, 0.0, 0.3), 0.001);
    FrameState prev, cur;
    prev.setPose(makePoseRPY(2, 1, 0, 0, 0, 0.3));
    prev.setVelocity(Vec3d(1, 0, 0));
    const imu::NavState pred = pre.predict(prev.nav(), {}, Vec3d(0, 0, -9.81));
    cur.setPose(pred.pose() * makePoseRPY(0.05, -0.02, 0.01, 0.01, 0, -0.02));  // off
    cur.setVelocity(pred.v + Vec3d(0.1, 0, 0));
    FrameProblemInputs in;
    in.prev = &prev;
    in.cur = &cur;
    in.imu = &pre;
    FusionParams p;
    p.max_iterations = 30;
    ASSERT_TRUE(solveFrame(in, p).usable);
    EXPECT_LT(translationDistance(cur.T_map_imu(), pred.pose()), 1e-5);
    EXPECT_LT(rotationAngle(cur.T_map_imu(), pred.pose()), 1e-6);
    EXPECT_LT((cur.velocity() - pred.v).norm(), 1e-4);
}

TEST(FrameProblem, RelativePosePriorHoldsAnUnconstrainedScan) {
    // Only the floor is seen: z, roll, pitch come from the scan; x, y, yaw only from the prior.
    const SE3d T_prev = makePoseRPY(0, 0, 0.5, 0, 0, 0);
    const SE3d delta = makePoseRPY(0.8, 0.1, 0, 0, 0, 0.05);
    const SE3d T_true = T_prev * delta;
    std::vector<Correspondence> floor;
    for (const auto& c : boxRoom(T_true, 400, 9))
        if (c.type == FeatureType::Plane && c.n.z() > 0.5 && c.q.z() < 1) floor.push_back(c);
    ASSERT_GT(floor.size(), 30u);
    ScanFactor scan(floor, 0.05);
    FrameState prev, cur;
    prev.setPose(T_prev);
    cur.setPose(T_true * makePoseRPY(0.2, -0.3, 0.05, 0.01, -0.01, 0.05));
    FrameProblemInputs in;
    in.prev = &prev;
    in.cur = &cur;
    in.scan = &scan;
    RelativePosePrior prior;
    prior.delta = delta;
    prior.sqrt_info = Mat6d::Identity() * 100;
    in.prior = prior;
    FusionParams p;
    p.max_iterations = 30;
    ASSERT_TRUE(solveFrame(in, p).usable);
    EXPECT_LT(translationDistance(cur.T_map_imu(), T_true), 1e-5);
    EXPECT_LT(rotationAngle(cur.T_map_imu(), T_true), 1e-6);
    // The previous pose stays fixed without IMU.
    EXPECT_LT(translationDistance(prev.T_map_imu(), T_prev), 1e-12);
}

TEST(RobustKernel, WeightsAndNames) {
    EXPECT_DOUBLE_EQ(robustWeight(RobustKernel::Huber, 0.05, 0.1), 1.0);
    EXPECT_DOUBLE_EQ(robustWeight(RobustKernel::Huber, 0.4, 0.1), 0.25);
    EXPECT_DOUBLE_EQ(robustWeight(RobustKernel::Cauchy, 0.1, 0.1), 0.5);
    EXPECT_EQ(robustKernelFromString("cauchy"), RobustKernel::Cauchy);
    EXPECT_THROW(robustKernelFromString("tukey"), std::invalid_argument);
}

namespace {
/// 0.1 s of IMU at rest-level specific force (no motion), the previous state at the origin.
imu::Preintegration stillImu() {
    imu::Preintegration pre(imu::ImuBias{}, imu::ImuNoise{0.02, 0.002});
    for (int k = 0; k < 100; ++k) pre.integrate(Vec3d(0, 0, 9.81), Vec3d::Zero(), 0.001);
    return pre;
}
/// The two-state IMU window over `pre` (and `scan` if given), the current state at t = 0.1 s,
/// asking for the marginal.
FrameProblemInputs imuWindow(FrameState& prev, FrameState& cur, const imu::Preintegration& pre,
                             ScanFactor* scan = nullptr) {
    cur.t = 0.1;
    FrameProblemInputs in;
    in.prev = &prev;
    in.cur = &cur;
    in.imu = &pre;
    in.scan = scan;
    in.marginalize = true;
    return in;
}
/// The plane correspondences of the box room whose normals are not along x: walls that leave x
/// blind.
std::vector<Correspondence> wallsAlongX() {
    std::vector<Correspondence> walls;
    for (const auto& c : boxRoom(SE3d::Identity(), 800, 4))
        if (c.type == FeatureType::Plane && std::abs(c.n.x()) < 0.5) walls.push_back(c);
    return walls;
}
Mat15d covarianceOf(const StatePrior& p) {
    const Mat15d info = p.sqrt_info.transpose() * p.sqrt_info;
    return info.inverse();
}
}  // namespace

// The marginal of an IMU-only window, checked against linear propagation by hand: the previous
// state is held by the fixed priors (position 2 cm, velocity 0.5 m/s per axis), the IMU says
// "no motion" over dt = 0.1 s with little noise, so the current position's variance per axis is
// sigma_p^2 + dt^2 sigma_v^2 = 4e-4 + 2.5e-3 = 2.9e-3 m^2 and the velocity's sigma_v^2 = 0.25
// (the attitude prior, 0.2 deg, adds g * 3.5e-3 * dt to the velocity: 1e-5 in variance).
TEST(FrameProblem, MarginalOfAnImuWindowMatchesPropagationByHand) {
    const imu::Preintegration pre = stillImu();
    FrameState prev, cur;
    FrameProblemInputs in = imuWindow(prev, cur, pre);
    FusionParams p;
    const auto s = solveFrame(in, p);
    ASSERT_TRUE(s.usable);
    ASSERT_TRUE(s.marginal.has_value());
    const Mat15d C = covarianceOf(*s.marginal);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(C(k, k), 2.9e-3, 0.05 * 2.9e-3) << k;
        EXPECT_NEAR(C(6 + k, 6 + k), 0.25, 0.02 * 0.25) << k;
        // Position and velocity are correlated: cov(p, v) = dt sigma_v^2 = 0.025.
        EXPECT_NEAR(C(k, 6 + k), 0.025, 0.05 * 0.025) << k;
    }
    // Without marginalize, none.
    in.marginalize = false;
    EXPECT_FALSE(solveFrame(in, p).marginal.has_value());
}

// A scan that sees only walls along x (normals y and z): the marginal keeps what the IMU window
// knows along x (variance as without the scan) and is sure along y and z; carried into the next
// frame's window as its previous state's prior, it lets the IMU velocity through along x.
TEST(FrameProblem, MarginalIsLooseAlongTheAxisTheScanMisses) {
    const std::vector<Correspondence> walls = wallsAlongX();
    ASSERT_GT(walls.size(), 100u);
    ScanFactor scan(walls, 0.05);
    const imu::Preintegration pre = stillImu();
    FrameState prev, cur;
    const FrameProblemInputs in = imuWindow(prev, cur, pre, &scan);
    FusionParams p;
    const auto s = solveFrame(in, p);
    ASSERT_TRUE(s.marginal.has_value());
    const Mat15d C = covarianceOf(*s.marginal);
    EXPECT_NEAR(C(0, 0), 2.9e-3, 0.05 * 2.9e-3);
    EXPECT_LT(C(1, 1), 3e-5);  // 0.05^2 / ~200 wall residuals per axis
    EXPECT_LT(C(2, 2), 3e-5);
    // Next frame: the state carried with its marginal, not the fixed 2 cm sigma.
    FrameState prev2 = cur, cur2 = cur;
    cur2.t = 0.2;
    FrameProblemInputs in2 = in;
    in2.prev = &prev2;
    in2.cur = &cur2;
    in2.prev_prior = &*s.marginal;
    const auto s2 = solveFrame(in2, p);
    ASSERT_TRUE(s2.marginal.has_value());
    const Mat15d C2 = covarianceOf(*s2.marginal);
    // x grows by dt^2 sigma_v^2 (the velocity is still only known from the first prior) plus
    // the cross terms: var(p + dt v) = 2.9e-3 + 2 dt 0.025 + dt^2 0.25 = 1.04e-2; the fixed
    // prior would have reset it to 2.9e-3.
    EXPECT_NEAR(C2(0, 0), 1.04e-2, 0.05 * 1.04e-2);
    EXPECT_LT(C2(1, 1), 3e-5);
}

// [fusion] prior_kernel. A walls-only scan (x blind) in an IMU window that says "no motion"
// (x known to ~5 cm), and an odom_alt prior that holds x at 1 cm per frame the way superloc's
// does on a blind axis. Without the loss an unreported jump of odom_alt is taken almost in full
// (1e4 against the window's ~350 m^-2). With the Cauchy loss at the default scale (10 sigmas) a
// 5 m jump, 500 sigmas off, pulls with a bounded force (about one sigma's worth: 6 cm); at 3
// sigmas a 1 m jump moves the pose by ~3 cm. A 1-sigma disagreement is taken as without it.
TEST(FrameProblem, CauchyPriorKernelBoundsAnUnreportedJumpOnTheBlindAxis) {
    ScanFactor scan(wallsAlongX(), 0.05);
    const imu::Preintegration pre = stillImu();
    const auto solveX = [&](double jump, const std::string& kernel, double sigmas) {
        FrameState prev, cur;
        FrameProblemInputs in = imuWindow(prev, cur, pre, &scan);
        RelativePosePrior prior;
        prior.delta = makePoseRPY(jump, 0, 0, 0, 0, 0);
        Vec6d W = Vec6d::Zero();
        W[0] = 1.0 / (0.01 * 0.01);
        prior.sqrt_info = sqrtInfo(W);
        in.prior = prior;
        FusionParams p;
        p.max_iterations = 50;
        p.active.prior_kernel = kernel;
        if (sigmas > 0) p.active.prior_kernel_sigmas = sigmas;
        EXPECT_TRUE(solveFrame(in, p).usable);
        return cur.T_map_imu().translation().x();
    };
    EXPECT_EQ(FusionParams{}.active.prior_kernel, "cauchy");
    EXPECT_GT(solveX(5.0, "none", 0), 4.5);
    const double robust = solveX(5.0, "cauchy", 0);  // the default scale
    EXPECT_GT(robust, 0.0);
    EXPECT_LT(robust, 0.1);
    EXPECT_GT(solveX(1.0, "none", 0), 0.9);
    const double tight = solveX(1.0, "cauchy", 3.0);
    EXPECT_GT(tight, 0.0);
    EXPECT_LT(tight, 0.06);
    const double small_none = solveX(0.01, "none", 0), small_cauchy = solveX(0.01, "cauchy", 0);
    EXPECT_GT(small_none, 0.009);
    EXPECT_NEAR(small_cauchy, small_none, 0.02 * small_none);
    FusionParams bad;
    bad.active.prior_kernel = "tukey";
    EXPECT_THROW(bad.validate(), ConfigError);
}

// The IMU factor's bias path. Samples of a rotating, accelerating motion carry a non-zero bias;
// the preintegration is linearised at zero bias. At the true states with the true biases the
// first-order bias correction brings the residual near zero; with the biases left at zero it is
// large. Then the factor's Jacobians (autodiff through the bias correction and the quaternion
// maps) against central differences in the tangent spaces, at a state away from the solution.
TEST(StatePriorFactor, AnalyticJacobiansAreTheAutodiffOnes) {
    // The solves' factor (analytic Jacobians) against the same residual differentiated with dual
    // numbers: the same residual, and the same Jacobian in each block's tangent (the pose's ambient
    // columns times PoseManifold's PlusJacobian), with a full correlated square-root information,
    // near the reference and far from it (rotations up to ~2.5 rad).
    std::mt19937 rng(8);
    std::normal_distribution<double> N(0, 1);
    PoseManifold m;
    for (int trial = 0; trial < 8; ++trial) {
        StatePrior sp;
        sp.T_ref = makePoseRPY(3 * N(rng), 3 * N(rng), N(rng), 0.3 * N(rng), 0.3 * N(rng), 2 * N(rng));
        for (int k = 0; k < 9; ++k) sp.sb_ref[k] = 0.1 * N(rng);
        Mat15d L = Mat15d::Zero();
        for (int i = 0; i < 15; ++i)
            for (int j = 0; j <= i; ++j) L(i, j) = i == j ? 10.0 + 5 * std::abs(N(rng)) : N(rng);
        sp.sqrt_info = L.transpose();
        const double far = trial < 4 ? 0.05 : 0.8;
        FrameState s;
        s.setPose(sp.T_ref * makePoseRPY(far * N(rng), far * N(rng), far * N(rng), far * N(rng), far * N(rng), far * N(rng)));
        for (int k = 0; k < 9; ++k) s.speed_bias[k] = sp.sb_ref[k] + 0.05 * N(rng);
        std::unique_ptr<ceres::CostFunction> analytic(StatePriorFactor::Create(sp));
        std::unique_ptr<ceres::CostFunction> autodiff(StatePriorFactor::CreateAutoDiff(sp));
        double* blocks[2] = {s.pose, s.speed_bias};
        Eigen::Matrix<double, 15, 7, Eigen::RowMajor> Pa, Pd;
        Eigen::Matrix<double, 15, 9, Eigen::RowMajor> Sa, Sd;
        double* ja[2] = {Pa.data(), Sa.data()};
        double* jd[2] = {Pd.data(), Sd.data()};
        Eigen::Matrix<double, 15, 1> ra, rd;
        ASSERT_TRUE(analytic->Evaluate(blocks, ra.data(), ja));
        ASSERT_TRUE(autodiff->Evaluate(blocks, rd.data(), jd));
        EXPECT_LT((ra - rd).norm(), 1e-12 * rd.norm()) << trial;
        double P[42];
        m.PlusJacobian(s.pose, P);
        const Eigen::Matrix<double, 7, 6, Eigen::RowMajor> Pm = Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>>(P);
        const Eigen::Matrix<double, 15, 6> Ta = Pa * Pm, Td = Pd * Pm;
        EXPECT_LT((Ta - Td).norm(), 1e-9 * Td.norm()) << trial;
        EXPECT_LT((Sa - Sd).norm(), 1e-12 * Sd.norm()) << trial;
    }
}

TEST(ImuFactor, AnalyticJacobiansAreTheAutodiffOnes) {
    // The solves' factor (analytic Jacobians) against the same residual differentiated with dual
    // numbers: the same residual, and the same Jacobian in each block's tangent (a pose's ambient
    // columns times PoseManifold's PlusJacobian), at states off the prediction and biases off
    // their linearisation point.
    imu::Preintegration pre(imu::ImuBias{Vec3d(0.02, -0.01, 0.03), Vec3d(0.002, -0.001, 0.003)},
                            imu::ImuNoise{0.02, 0.002});
    for (int k = 0; k < 40; ++k) pre.integrate(Vec3d(0.4, 0.2, 9.7), Vec3d(0.2, -0.3, 0.5), 0.005);
    const Vec3d g(0, 0, -9.81);
    std::unique_ptr<ceres::CostFunction> analytic(ImuFactor::Create(pre, g, 0.001, 0.0001));
    std::unique_ptr<ceres::CostFunction> autodiff(ImuFactor::CreateAutoDiff(pre, g, 0.001, 0.0001));
    std::mt19937 rng(3);
    std::normal_distribution<double> N(0, 1);
    PoseManifold m;
    for (int trial = 0; trial < 5; ++trial) {
        FrameState si, sj;
        si.setPose(makePoseRPY(1 + N(rng), 2 * N(rng), 0.5, 0.3 * N(rng), 0.3 * N(rng), 2 * N(rng)));
        si.setVelocity(Vec3d(N(rng), N(rng), 0.1 * N(rng)));
        si.setBias({Vec3d(0.1 * N(rng), 0.1 * N(rng), 0.1 * N(rng)), Vec3d(0.01 * N(rng), 0.01 * N(rng), 0.01 * N(rng))});
        sj.setPose(si.T_map_imu() * makePoseRPY(0.2 + 0.05 * N(rng), 0.05 * N(rng), 0.02 * N(rng), 0.1 * N(rng),
                                                 0.1 * N(rng), 0.2 + 0.1 * N(rng)));
        sj.setVelocity(si.velocity() + Vec3d(0.1 * N(rng), 0.1 * N(rng), 0.1 * N(rng)));
        sj.setBias({Vec3d(0.1 * N(rng), 0.1 * N(rng), 0.1 * N(rng)), Vec3d(0.01 * N(rng), 0.01 * N(rng), 0.01 * N(rng))});
        double* blocks[4] = {si.pose, si.speed_bias, sj.pose, sj.speed_bias};
        const int sizes[4] = {7, 9, 7, 9};
        std::vector<double> Ja[4], Jd[4];
        double* pa[4];
        double* pd[4];
        for (int k = 0; k < 4; ++k) {
            Ja[k].resize(15 * sizes[k]), Jd[k].resize(15 * sizes[k]);
            pa[k] = Ja[k].data(), pd[k] = Jd[k].data();
        }
        Eigen::Matrix<double, 15, 1> ra, rd;
        ASSERT_TRUE(analytic->Evaluate(blocks, ra.data(), pa));
        ASSERT_TRUE(autodiff->Evaluate(blocks, rd.data(), pd));
        EXPECT_LT((ra - rd).norm(), 1e-12 * rd.norm()) << trial;
        for (int k = 0; k < 4; ++k) {
            using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
            Eigen::MatrixXd A = Eigen::Map<RowMat>(Ja[k].data(), 15, sizes[k]);
            Eigen::MatrixXd D = Eigen::Map<RowMat>(Jd[k].data(), 15, sizes[k]);
            if (sizes[k] == 7) {
                double P[42];
                m.PlusJacobian(blocks[k], P);
                const Eigen::Matrix<double, 7, 6, Eigen::RowMajor> Pm = Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>>(P);
                A = A * Pm;
                D = D * Pm;
            }
            EXPECT_LT((A - D).norm(), 1e-8 * D.norm()) << "trial " << trial << " block " << k << "\n" << A << "\n\n" << D;
        }
    }
}

TEST(FrameProblem, WindowInformationIsCeresProblemsMarginal) {
    // imuWindowStateInformation evaluates the window's factors one by one (no Ceres problem):
    // the same information as Ceres' Jacobian of the same factors in a problem, the previous
    // state eliminated, in StatePriorFactor's coordinates. With odom_alt's prior and a
    // previous-state prior that correlates its blocks.
    imu::Preintegration pre(imu::ImuBias{Vec3d(0.02, -0.01, 0.03), Vec3d(0.002, -0.001, 0.003)},
                            imu::ImuNoise{0.02, 0.002});
    for (int k = 0; k < 20; ++k) pre.integrate(Vec3d(0.4, 0.2, 9.7), Vec3d(0.2, -0.3, 0.5), 0.005);
    FrameState prev, cur;
    prev.setPose(makePoseRPY(3, -2, 0.5, 0.1, -0.05, 0.8));
    prev.setVelocity(Vec3d(1.0, 0.3, 0.0));
    prev.setBias({Vec3d(0.05, 0.0, -0.02), Vec3d(0.001, 0.002, 0.0)});
    cur.setPose(prev.T_map_imu() * makePoseRPY(0.1, 0.03, 0.0, 0.01, 0.0, 0.05));
    cur.setVelocity(Vec3d(1.1, 0.35, 0.01));
    cur.setBias({Vec3d(0.051, 0.0, -0.02), Vec3d(0.001, 0.002, 0.0001)});
    StatePrior pp;
    pp.T_ref = prev.T_map_imu() * makePoseRPY(0.01, 0, 0, 0, 0.002, 0);
    std::mt19937 rng(5);
    std::normal_distribution<double> N(0, 1);
    Mat15d L = Mat15d::Zero();
    for (int i = 0; i < 15; ++i)
        for (int j = 0; j <= i; ++j) L(i, j) = i == j ? 20.0 + 5 * std::abs(N(rng)) : N(rng);
    pp.sqrt_info = L.transpose();
    RelativePosePrior rel;
    rel.delta = prev.T_map_imu().inverse() * cur.T_map_imu() * makePoseRPY(0.02, 0, 0, 0, 0, 0.01);
    rel.sqrt_info = Vec6d(50, 40, 30, 200, 300, 100).asDiagonal();
    FusionParams params;
    FrameProblemInputs in;
    in.prev = &prev;
    in.cur = &cur;
    in.setImu(&pre, imu::ImuParams{});
    in.prev_prior = &pp;
    in.prior = rel;
    const auto direct = imuWindowStateInformation(in, params);
    ASSERT_TRUE(direct.has_value());
    // The same factors in a Ceres problem.
    FrameState a = prev, b = cur;
    static PoseManifold manifold;
    ceres::Problem::Options popt;
    popt.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(popt);
    for (FrameState* st : {&a, &b}) {
        problem.AddParameterBlock(st->pose, 7, &manifold);
        problem.AddParameterBlock(st->speed_bias, 9);
    }
    problem.AddResidualBlock(ImuFactor::CreateAutoDiff(pre, in.g_map, in.acc_bias_rw, in.gyro_bias_rw), nullptr, a.pose,
                             a.speed_bias, b.pose, b.speed_bias);
    problem.AddResidualBlock(StatePriorFactor::Create(pp), nullptr, a.pose, a.speed_bias);
    problem.AddResidualBlock(RelativePoseFactor::Create(rel.delta, rel.sqrt_info), nullptr, a.pose, b.pose);
    ceres::Problem::EvaluateOptions eo;
    eo.parameter_blocks = {a.pose, a.speed_bias, b.pose, b.speed_bias};
    ceres::CRSMatrix crs;
    ASSERT_TRUE(problem.Evaluate(eo, nullptr, nullptr, nullptr, &crs));
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
    for (int r = 0; r < crs.num_rows; ++r)
        for (int k = crs.rows[r]; k < crs.rows[r + 1]; ++k) J(r, crs.cols[k]) = crs.values[k];
    const Eigen::MatrixXd H = J.transpose() * J;
    const Mat15d Hpp = H.topLeftCorner(15, 15), Hcc = H.bottomRightCorner(15, 15), Hcp = H.bottomLeftCorner(15, 15);
    Mat15d M = Hcc - Hcp * Hpp.ldlt().solve(Hcp.transpose());
    Mat15d A = Mat15d::Identity();
    A.topLeftCorner<3, 3>() = cur.T_map_imu().linear().transpose();
    M = A * M * A.transpose();
    EXPECT_LT((*direct - M).norm(), 1e-8 * M.norm()) << *direct << "\n\n" << M;
}

TEST(ImuFactor, BiasPathResidualAndJacobians) {
    const imu::ImuBias b{Vec3d(0.08, -0.05, 0.1), Vec3d(0.01, -0.006, 0.004)};
    const Vec3d w(0.2, -0.3, 0.5), a_body(0.4, 0.2, -0.1), g(0, 0, -9.81);
    const double dt = 0.005;
    const int n = 40;  // 0.2 s
    imu::Preintegration pre(imu::ImuBias{}, imu::ImuNoise{0.02, 0.002});
    imu::Preintegration pre_true(b, imu::ImuNoise{0.02, 0.002});
    FrameState si;
    si.setPose(makePoseRPY(1, 2, 0.5, 0.1, -0.05, 0.7));
    si.setVelocity(Vec3d(1.0, -0.5, 0.1));
    Mat3d R = si.T_map_imu().linear();
    for (int k = 0; k < n; ++k) {
        // Specific force of a body accelerating at a_body (body axes) under gravity.
        const Vec3d f = a_body - R.transpose() * g;
        pre.integrate(f + b.acc, w + b.gyro, dt);
        pre_true.integrate(f + b.acc, w + b.gyro, dt);
        R = R * expSO3(w * dt);
    }
    si.setBias(b);
    const imu::NavState nj = pre_true.predict(si.nav(), b, g);
    FrameState sj;
    sj.setPose(nj.pose());
    sj.setVelocity(nj.v);
    sj.setBias(b);
    ImuFactor f(pre, g, 0.001, 0.0001);
    Eigen::Matrix<double, 15, 1> r_true, r_zero;
    f(si.pose, si.speed_bias, sj.pose, sj.speed_bias, r_true.data());
    FrameState si0 = si, sj0 = sj;
    si0.setBias({});
    sj0.setBias({});
    f(si0.pose, si0.speed_bias, sj0.pose, sj0.speed_bias, r_zero.data());
    EXPECT_LT(r_true.norm(), 0.05 * r_zero.norm()) << r_true.transpose() << "\n" << r_zero.transpose();
    EXPECT_GT(r_zero.norm(), 3.0);  // whitened: sigmas off without the bias

    // Jacobians at a perturbed state (residual far from zero, biases off their linearisation).
    FrameState pi = si, pj = sj;
    pj.setPose(sj.T_map_imu() * makePoseRPY(0.03, -0.02, 0.01, 0.01, -0.02, 0.015));
    pj.setVelocity(sj.velocity() + Vec3d(0.05, 0.02, -0.03));
    pi.setBias({Vec3d(0.1, -0.02, 0.05), Vec3d(0.02, -0.01, 0.0)});
    std::unique_ptr<ceres::CostFunction> cf(ImuFactor::Create(pre, g, 0.001, 0.0001));
    double* blocks[4] = {pi.pose, pi.speed_bias, pj.pose, pj.speed_bias};
    const int sizes[4] = {7, 9, 7, 9};
    std::vector<std::vector<double>> J(4);
    std::vector<double*> jp(4);
    for (int k = 0; k < 4; ++k) J[k].resize(15 * sizes[k]), jp[k] = J[k].data();
    Eigen::Matrix<double, 15, 1> r0;
    ASSERT_TRUE(cf->Evaluate(blocks, r0.data(), jp.data()));
    PoseManifold m;
    for (int k = 0; k < 4; ++k) {
        const bool pose = sizes[k] == 7;
        const int tangent = pose ? 6 : 9;
        Eigen::MatrixXd Jt = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            J[k].data(), 15, sizes[k]);
        if (pose) {
            double P[42];
            m.PlusJacobian(blocks[k], P);
            Jt = Jt * Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>>(P);
        }
        std::vector<double> saved(blocks[k], blocks[k] + sizes[k]);
        const double h = 1e-6;
        for (int c = 0; c < tangent; ++c) {
            Eigen::Matrix<double, 15, 1> rp, rm;
            for (double sgn : {1.0, -1.0}) {
                std::vector<double> x = saved;
                if (pose) {
                    double d[6] = {0, 0, 0, 0, 0, 0};
                    d[c] = sgn * h;
                    m.Plus(saved.data(), d, x.data());
                } else {
                    x[c] += sgn * h;
                }
                std::copy(x.begin(), x.end(), blocks[k]);
                cf->Evaluate(blocks, (sgn > 0 ? rp : rm).data(), nullptr);
            }
            std::copy(saved.begin(), saved.end(), blocks[k]);
            const Eigen::Matrix<double, 15, 1> num = (rp - rm) / (2 * h);
            EXPECT_LT((num - Jt.col(c)).norm(), 1e-4 * std::max(1.0, num.norm())) << "block " << k << " column " << c;
        }
    }
}
