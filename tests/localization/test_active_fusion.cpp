// Active sensor fusion (issue 5, doc/method.md §2): the prior information W = diag(max(0, 1-gamma)) s,
// the scan information it is scaled to, Zhang's eigen remap, the observability scan, and the
// methods superloc / passive / eigen_remap in the Localizer on a synthetic corridor (x
// unobservable). The risk scenes themselves (plane -> x y yaw, corridor -> x, room -> none) are in
// tests/risk.
#include <gtest/gtest.h>
#include <fstream>
#include <iterator>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/fusion/frame_problem.h>
#include <superloc/fusion/prior_weight.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/localization/localizer.h>
#include <superloc/app/observability_scan.h>
#include <superloc/risk/alignment_risk.h>

#include <cmath>
#include <filesystem>

using namespace superloc;
using namespace superloc::fusion;

namespace {

// Corridor along x: walls y = -2 / 2, floor z = -1, ceiling z = 2 (map frame), open ends.
struct Plane {
    int axis;
    double offset;
};
const std::vector<Plane> kCorridor = {{1, -2}, {1, 2}, {2, -1}, {2, 2}};

// Rays from the body pose T (sensor at the body origin): hits within 30 m as point-to-plane
// correspondences (scan point in the body frame, exact map plane) and as risk inputs.
void castCorridor(const SE3d& T, std::vector<Correspondence>& corr,
                  std::vector<Correspondence>& risk_in, int n_az = 120, int n_el = 16) {
    corr.clear();
    risk_in.clear();
    for (int e = 0; e < n_el; ++e) {
        const double el = (-30.0 + 60.0 * (e + 0.5) / n_el) * kDeg;
        for (int a = 0; a < n_az; ++a) {
            const double az = 2 * M_PI * (a + 0.5) / n_az;
            const Vec3d d_b(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
            const Vec3d d = T.linear() * d_b, o = T.translation();
            double best = 30;
            int hit = -1;
            for (size_t k = 0; k < kCorridor.size(); ++k) {
                const double dk = d[kCorridor[k].axis];
                if (std::abs(dk) < 1e-12) continue;
                const double t = (kCorridor[k].offset - o[kCorridor[k].axis]) / dk;
                if (t > 0 && t < best) best = t, hit = static_cast<int>(k);
            }
            if (hit < 0) continue;
            Correspondence c;
            c.p = best * d_b;
            c.q = o + best * d;  // the hit, exactly on the plane
            c.q[kCorridor[hit].axis] = kCorridor[hit].offset;
            c.n = Vec3d::Unit(kCorridor[hit].axis);
            c.type = FeatureType::Plane;
            corr.push_back(c);
            Correspondence r;
            r.p = c.p;
            r.n = T.linear().transpose() * c.n;
            if (r.n.dot(r.p) > 0) r.n = -r.n;
            risk_in.push_back(r);
        }
    }
}
}  // namespace

TEST(PriorWeight, InformationIsOneMinusGammaTimesScale) {
    Vec6d gamma, s;
    gamma << 0.0, 0.5, 1.0, 1.0, 0.19, 0.9;
    s << 100, 100, 100, 4000, 4000, 4000;
    const Vec6d W = activeInformation(gamma, s);
    EXPECT_DOUBLE_EQ(W[0], 100);  // fully degenerate: the whole scale
    EXPECT_DOUBLE_EQ(W[1], 50);
    EXPECT_DOUBLE_EQ(W[2], 0);  // well constrained: no prior at all
    EXPECT_DOUBLE_EQ(W[3], 0);
    EXPECT_NEAR(W[4], 0.81 * 4000, 1e-9);
    EXPECT_NEAR(W[5], 0.1 * 4000, 1e-9);
    const Mat6d S = sqrtInfo(W);
    EXPECT_NEAR(S(0, 0), 10, 1e-12);
    EXPECT_EQ(S(2, 2), 0);
    EXPECT_EQ(S(0, 1), 0);
    ActiveFusionParams ap;
    ap.passive_sigma_xyz = 0.1;
    ap.passive_sigma_rot_deg = 1.0;
    const Vec6d Wp = passiveInformation(ap);
    EXPECT_NEAR(Wp[0], 100, 1e-9);
    EXPECT_NEAR(Wp[5], 1 / (kDeg * kDeg), 1e-6);
}

TEST(PriorWeight, ScanInformationMatchesNumericBodyJacobian) {
    // H = sum w J^T J / sigma^2 with J the residual's derivative w.r.t. a body perturbation
    // T Exp(d) (toVec6 order), checked against central differences, at a rotated pose.
    const SE3d T = makePoseRPY(3, -1, 0.5, 0.1, -0.2, 0.7);
    std::vector<Correspondence> corr;
    std::vector<Correspondence> unused;
    castCorridor(T, corr, unused, 12, 4);
    ASSERT_GT(corr.size(), 20u);
    corr[1].weight = 0.3;
    const double sigma = 0.05;
    Mat6d Hn = Mat6d::Zero();
    for (const auto& c : corr) {
        Vec6d row;
        for (int k = 0; k < 6; ++k) {
            Vec6d d = Vec6d::Zero();
            d[k] = 1e-6;
            double rp, rm;
            correspondenceResidual(c, (T * fromVec6(d)).linear(), (T * fromVec6(d)).translation(),
                                   &rp, nullptr);
            correspondenceResidual(c, (T * fromVec6(-d)).linear(), (T * fromVec6(-d)).translation(),
                                   &rm, nullptr);
            row[k] = (rp - rm) / 2e-6;
        }
        Hn += c.weight * row * row.transpose() / (sigma * sigma);
    }
    const Mat6d H = scanInformation(corr, T, sigma);
    EXPECT_LT((H - Hn).norm() / Hn.norm(), 1e-6);
    const Vec6d s = priorScale(H);
    const double tr_t = H.topLeftCorner<3, 3>().trace(), tr_r = H.bottomRightCorner<3, 3>().trace();
    EXPECT_NEAR(s[0], tr_t / 3, 1e-9);
    EXPECT_NEAR(s[5], tr_r / 3, 1e-9);
}

TEST(PriorWeight, ScanInformationIsTheResidualsJacobianTurnedBitForBit) {
    // scanInformation takes each row from correspondenceBodyJacobian (no residual computed):
    // the same products as correspondenceResidual's Jacobian with its translation turned by R^T,
    // so H is the same to the bit, for planes, lines and points (the pose covariance and the
    // weighting read it three times a frame: doc/results.md "Cost of the risk and the weighting").
    const SE3d T = makePoseRPY(3, -1, 0.5, 0.1, -0.2, 0.7);
    std::vector<Correspondence> corr, unused;
    castCorridor(T, corr, unused, 12, 4);
    ASSERT_GT(corr.size(), 20u);
    for (size_t i = 0; i < corr.size(); ++i) {
        corr[i].weight = 0.2 + 0.1 * static_cast<double>(i % 7);
        if (i % 3 == 1) corr[i].type = FeatureType::Line, corr[i].n = Vec3d(0.3, -0.8, 0.52).normalized();
        if (i % 3 == 2) corr[i].type = FeatureType::Point;
    }
    const Mat3d R = T.linear();
    Mat6d Hr = Mat6d::Zero();
    double r[3], J[18];
    for (const auto& c : corr) {
        correspondenceResidual(c, R, T.translation(), r, J);
        for (int k = 0; k < residualDim(c.type); ++k) {
            Vec6d row = Eigen::Map<const Vec6d>(J + 6 * k);
            row.head<3>() = R.transpose() * row.head<3>();
            Hr.noalias() += c.weight * row * row.transpose();
        }
    }
    const double sigma = 0.05;
    Hr /= sigma * sigma;
    const Mat6d H = scanInformation(corr, T, sigma);
    for (int i = 0; i < 6; ++i)
        for (int k = 0; k < 6; ++k) EXPECT_EQ(H(i, k), Hr(i, k)) << i << "," << k;
}

TEST(PriorWeight, CorridorPriorWinsOnXOnly) {
    // Issue 5 "Must show": in a corridor (x unobservable) a relative-pose prior that disagrees
    // along x by 20 cm, weighted W = diag(max(0, 1 - gamma)) s, sets x, and moves the healthy
    // axes by < 1 mm / 0.01 deg. Without the prior, x stays wherever the initial guess put it.
    const SE3d T_prev = makePoseRPY(2, 0.1, 0.2, 0, 0, 0);
    const SE3d delta_true = makePoseRPY(0.5, 0.02, -0.01, 0, 0, 0);
    const SE3d T_true = T_prev * delta_true;
    std::vector<Correspondence> corr;
    std::vector<Correspondence> risk_in;
    castCorridor(T_true, corr, risk_in);
    const auto risk = risk::computeAlignmentRisk(risk_in, risk::RiskParams{});
    ASSERT_EQ(risk::degenerateAxes(risk), "x");

    const SE3d guess = T_true * makePoseRPY(0.05, 0.03, -0.02, 0.2 * kDeg, -0.3 * kDeg, 0.5 * kDeg);
    const Mat6d H = scanInformation(corr, guess, 0.05);
    const Vec6d W = activeInformation(risk.gamma, priorScale(H));
    EXPECT_GT(W[0], 0.5 * priorScale(H)[0]);  // the prior holds x...
    EXPECT_GT(W[0], 100 * H(0, 0));           // ...far above what the scan says about x
    EXPECT_EQ(W[1], 0);                       // y: both walls, gamma_y clamps at 1: no prior
    EXPECT_LT(W[2], 0.5 * W[0]);  // z: healthy, gamma_z ~0.8 (walls dominate these rays): a little

    const auto solve = [&](std::optional<RelativePosePrior> prior) {
        ScanFactor scan(corr, 0.05);
        FrameState prev, cur;
        prev.setPose(T_prev);
        cur.setPose(guess);
        FrameProblemInputs in;
        in.prev = &prev;
        in.cur = &cur;
        in.scan = &scan;
        in.prior = prior;
        FusionParams p;
        p.max_iterations = 30;
        EXPECT_TRUE(solveFrame(in, p).usable);
        return cur.T_map_imu();
    };
    const SE3d x_off = makePoseRPY(0.2, 0, 0, 0, 0, 0);
    RelativePosePrior prior;
    prior.delta = delta_true * x_off;  // odom_alt says 20 cm further along x
    prior.sqrt_info = sqrtInfo(W);
    const SE3d with = solve(prior);
    const SE3d without = solve(std::nullopt);
    const Vec6d e_with = toVec6(T_true.inverse() * with);
    const Vec6d e_without = toVec6(T_true.inverse() * without);
    EXPECT_NEAR(e_with[0], 0.2, 1e-3);  // the prior wins on x
    for (int k = 1; k < 3; ++k)
        EXPECT_LT(std::abs(e_with[k] - e_without[k]), 1e-3) << kAxisNames[k];
    for (int k = 3; k < 6; ++k)
        EXPECT_LT(std::abs(e_with[k] - e_without[k]) / kDeg, 0.01) << kAxisNames[k];
    for (int k = 1; k < 3; ++k) EXPECT_LT(std::abs(e_with[k]), 1e-3) << kAxisNames[k];
    EXPECT_NEAR(e_without[0], 0.05, 5e-3);  // scan alone: x stays at the guess
}

TEST(EigenRemap, ProjectsOutTheWeakEigenDirection) {
    Mat6d H = Mat6d::Zero();
    H.diagonal() << 1e-4, 0.4, 0.5, 20, 30, 40;
    const SE3d T_ref = makePoseRPY(1, 2, 3, 0, 0, 0.3);
    const SE3d T_solved = T_ref * makePoseRPY(0.4, 0.02, -0.01, 0, 0, 0.001);
    const RemapResult r = eigenRemap(T_ref, T_solved, H, 0.05);
    EXPECT_EQ(r.removed, 1);
    const Vec6d d = toVec6(T_ref.inverse() * r.T);
    EXPECT_NEAR(d[0], 0, 1e-9);  // weak direction: from the reference
    EXPECT_NEAR(d[1], 0.02, 1e-6);
    EXPECT_NEAR(d[2], -0.01, 1e-6);
    EXPECT_NEAR(d[5], 0.001, 1e-6);
    EXPECT_NEAR(r.prior_share[0], 1, 1e-9);
    EXPECT_NEAR(r.prior_share[1], 0, 1e-9);
    // Nothing below the threshold: the solution is kept.
    const RemapResult keep = eigenRemap(T_ref, T_solved, H, 1e-5);
    EXPECT_EQ(keep.removed, 0);
    EXPECT_LT(translationDistance(keep.T, T_solved), 1e-9);
    // Per group, as shares of the group's trace: a yaw eigenvalue of 0.5 rad^-2 is larger than
    // every translation one but only 0.5 % of its group (50, 50, 0.5), so yaw is removed, and
    // x (share 0.33) is kept although its value is 100x below yaw's.
    Mat6d H2 = Mat6d::Zero();
    H2.diagonal() << 0.005, 0.005, 0.005, 50, 50, 0.5;
    const RemapResult g = eigenRemap(T_ref, T_solved, H2, 0.2 / 3);
    EXPECT_EQ(g.removed, 1);
    EXPECT_NEAR(g.prior_share[5], 1, 1e-9);
    EXPECT_NEAR(g.prior_share[0], 0, 1e-9);
    EXPECT_NEAR(toVec6(T_ref.inverse() * g.T)[0], 0.4, 1e-6);
    EXPECT_NEAR(toVec6(T_ref.inverse() * g.T)[5], 0.0, 1e-9);
}

TEST(ObservabilityScan, VoxelMajorityColourAndPly) {
    app::ObservabilityScan obs(0.5);
    obs.add(
        {Vec3f(0.1f, 0.1f, 0.1f), Vec3f(0.2f, 0.1f, 0.1f), Vec3f(0.3f, 0.2f, 0.1f), Vec3f(5, 0, 0)},
        {0, 1, 1, 2});
    obs.add({Vec3f(5.1f, 0.1f, 0), Vec3f(9, 9, 9)}, {2, risk::kNoLabel});
    ASSERT_EQ(obs.size(), 3u);
    const PointCloud c = obs.cloud();
    ASSERT_EQ(c.rgb.size(), 3u);
    EXPECT_EQ(c.rgb[0], (std::array<uint8_t, 3>{0, 255, 0}));  // y wins 2 to 1
    EXPECT_EQ(c.rgb[1], (std::array<uint8_t, 3>{0, 0, 255}));  // z
    EXPECT_EQ(c.rgb[2], (std::array<uint8_t, 3>{128, 128, 128}));
    const std::string path =
        (std::filesystem::temp_directory_path() / "superloc_test_observability_scan.ply").string();
    obs.write(path);
    const PointCloud back = io::loadPointCloud(path);
    ASSERT_EQ(back.size(), 3u);
    ASSERT_EQ(back.rgb.size(), 3u);
    EXPECT_EQ(back.rgb[1], c.rgb[1]);
    // Written in place (no cloud built), the bytes of the cloud saved as PLY.
    const std::string via_cloud = path + ".cloud.ply";
    io::savePointCloud(via_cloud, c);
    std::ifstream a(path, std::ios::binary), b(via_cloud, std::ios::binary);
    const std::string bytes_a((std::istreambuf_iterator<char>(a)), {}), bytes_b((std::istreambuf_iterator<char>(b)), {});
    EXPECT_EQ(bytes_a, bytes_b);
    EXPECT_GT(bytes_a.size(), 3u * 15u);
    std::filesystem::remove(path);
    std::filesystem::remove(via_cloud);
}

namespace {
// The Localizer in the same corridor: no IMU, a surging motion along x (constant-velocity
// prediction off by ~2 cm per frame), exact odom_alt. x is unobservable for the scan, so icp
// keeps the prediction's x error while the prior methods take x from odom_alt.
SE3d corridorMotion(double t) {
    return makePoseRPY(t + 0.3 * std::sin(3 * t), 0.1 * std::sin(t), 0.3, 0, 0, 0.03 * std::sin(t));
}

Scan corridorScan(const SE3d& T, double t) {
    Scan s;
    s.t = t;
    for (int e = 0; e < 16; ++e) {
        const double el = (-30.0 + 4.0 * e) * kDeg;
        for (int a = 0; a < 360; ++a) {
            const double az = a * kDeg;
            const Vec3d d_b(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
            const Vec3d d = T.linear() * d_b, o = T.translation();
            double best = 1e9;
            for (const auto& P : kCorridor) {
                if (std::abs(d[P.axis]) < 1e-12) continue;
                const double r = (P.offset - o[P.axis]) / d[P.axis];
                if (r > 0) best = std::min(best, r);
            }
            if (best < 40) s.points.push_back((best * d_b).cast<float>());
        }
    }
    return s;
}

std::shared_ptr<map::PriorMap> corridorMap() {
    PointCloud c;
    for (double x = -20; x <= 40; x += 0.1) {
        for (double z = -1; z <= 2; z += 0.1)
            c.points.emplace_back(x, -2, z), c.points.emplace_back(x, 2, z);
        for (double y = -2; y <= 2; y += 0.1)
            c.points.emplace_back(x, y, -1), c.points.emplace_back(x, y, 2);
    }
    map::MapParams mp;
    mp.voxel_size = 0.1;
    return std::make_shared<map::PriorMap>(c, mp, Vec3f(0, 0, 0.5));
}

struct CorridorRun {
    double first_err_x = 0, max_err_x = 0, max_err_yz = 0;
    size_t frames = 0, prior_used = 0, flagged_x = 0;
    Vec6d last_prior_w = Vec6d::Zero();
    std::vector<int> prior_frames;
};

/// odom_alt is left out for t in (gap_from, gap_to).
CorridorRun runCorridor(const std::shared_ptr<map::PriorMap>& map, const std::string& method,
                        bool odom_alt, double gap_from = 1e9, double gap_to = 1e9) {
    localization::LocalizerParams p;
    p.loc.method = localization::methodFromString(method);
    p.features.voxel_size = 0.3;
    localization::Localizer loc(p, map);
    loc.setMinLoggingLevel(mrpt::system::LVL_ERROR);
    loc.setInitialPose(corridorMotion(0.1));
    CorridorRun out;
    for (int k = 1; k <= 25; ++k) {
        const double t = 0.1 * k;
        if (odom_alt)  // 20 Hz, in its own frame (offset from the map)
            for (double to = t - 0.1 + 0.05; to <= t + 1e-9; to += 0.05)
                if (to <= gap_from || to >= gap_to)
                    loc.addOdomAlt(
                        {to, makePoseRPY(5, -3, 1, 0, 0, 1.0) * corridorMotion(to), std::nullopt});
        const SE3d truth = corridorMotion(t);
        const auto r = loc.process(corridorScan(truth, t));
        const Vec3d e = r.T_map_lidar.translation() - truth.translation();
        // x error relative to the first frame's (x is unobservable there too: the first
        // frame's scan-only solve may slide a little along the corridor).
        if (k == 1) out.first_err_x = e.x();
        out.max_err_x = std::max(out.max_err_x, std::abs(e.x() - out.first_err_x));
        out.max_err_yz = std::max(out.max_err_yz, e.tail<2>().norm());
        out.frames++;
        out.prior_used += r.prior_used;
        if (r.prior_used) out.prior_frames.push_back(k);
        out.flagged_x += r.degenerate[0];
        if (r.prior_used) out.last_prior_w = r.prior_weight;
    }
    return out;
}
}  // namespace

TEST(ActiveFusion, CorridorMethodsAgainstIcp) {
    const auto map = corridorMap();
    const CorridorRun icp = runCorridor(map, "icp", true);
    const CorridorRun sl = runCorridor(map, "superloc", true);
    const CorridorRun paper = runCorridor(map, "superloc_paper", true);
    const CorridorRun pas = runCorridor(map, "passive", true);
    const CorridorRun eig = runCorridor(map, "eigen_remap", true);
    // The scene is degenerate in x on (nearly) every frame, for every method (without IMU the
    // estimate is the scan's: x weak where gamma_x is low).
    for (const auto* r : {&icp, &sl, &paper, &pas, &eig}) EXPECT_GE(r->flagged_x, r->frames - 1);
    // icp drifts along x with the constant-velocity prediction; the others follow odom_alt.
    EXPECT_GT(icp.max_err_x, 0.05);
    // superloc_paper holds x at the scan's own information scale; superloc at what odom_alt is
    // worth (no covariance, no held axis to calibrate on: the passive sigmas, 2 cm per frame),
    // predicting and deskewing with its motion.
    EXPECT_LT(paper.max_err_x, 0.002);
    EXPECT_LT(sl.max_err_x, 0.01);
    EXPECT_LT(eig.max_err_x, 0.01);
    // passive: a fixed 2 cm prior competes with the scan's small spurious x information (map
    // voxels, plane fits), so it follows odom_alt less closely than superloc_paper; better than icp.
    EXPECT_LT(pas.max_err_x, icp.max_err_x);
    for (const auto* r : {&icp, &sl, &paper, &pas, &eig}) EXPECT_LT(r->max_err_yz, 0.01);
    // superloc's and superloc_paper's priors are on x only: along the weak direction, gamma_y,
    // gamma_z >= 1 in a corridor.
    EXPECT_EQ(icp.prior_used, 0u);
    for (const auto* r : {&sl, &paper}) {
        EXPECT_EQ(r->prior_used, r->frames - 1);  // not on the first frame
        EXPECT_GT(r->last_prior_w[0], 0);
        EXPECT_LT(r->last_prior_w[1], 0.01 * r->last_prior_w[0]);
        EXPECT_LT(r->last_prior_w[2], 0.1 * r->last_prior_w[0]);
    }
    EXPECT_EQ(paper.last_prior_w[1], 0);
    EXPECT_EQ(pas.prior_used, pas.frames - 1);
    EXPECT_GT(eig.prior_used, 0u);
}

TEST(ActiveFusion, EveryMethodConstructsUnknownIsConfigError) {
    const auto map = corridorMap();
    for (const char* name : {"icp", "ndt", "superloc", "superloc_paper", "passive", "eigen_remap"}) {
        localization::LocalizerParams p;
        p.loc.method = localization::methodFromString(name);
        EXPECT_NO_THROW(localization::Localizer(p, map)) << name;
    }
    // The name is parsed once, where the INI is read: an unknown one stops there.
    mrpt::config::CConfigFileMemory c;
    c.write("localization", "method", "active");
    localization::LocalizationParams lp;
    EXPECT_THROW(lp.loadFromConfigFile(c, "localization"), superloc::ConfigError);
    // So does a negative share of the last scan's registration (0: every feature).
    mrpt::config::CConfigFileMemory d;
    d.write("localization", "last_scan_features", "-1");
    lp.loadFromConfigFile(d, "localization");
    EXPECT_EQ(lp.last_scan_features, -1);
    EXPECT_THROW(lp.validate(), superloc::ConfigError);
    d.write("localization", "last_scan_features", "0");
    lp.loadFromConfigFile(d, "localization");
    EXPECT_NO_THROW(lp.validate());
}

TEST(ActiveFusion, WithoutOdomAltTheFlagsStayAndNoPriorIsUsed) {
    const CorridorRun sl = runCorridor(corridorMap(), "superloc", false);
    EXPECT_EQ(sl.prior_used, 0u);
    EXPECT_GE(sl.flagged_x, sl.frames - 1);  // degenerate x still reported
    EXPECT_LT(sl.max_err_yz, 0.01);
}

TEST(ActiveFusion, OdomAltGapSkipsThePriorThenResumes) {
    // odom_alt missing for 0.8 s (> the 0.5 s interpolation limit) around frames 10-17.
    const CorridorRun sl = runCorridor(corridorMap(), "superloc", true, 0.95, 1.75);
    for (int k : sl.prior_frames)
        EXPECT_TRUE(k < 10 || k > 17) << "prior used in the gap, frame " << k;
    EXPECT_GE(sl.prior_used, 15u);  // before and after the gap
    EXPECT_GE(sl.flagged_x, sl.frames - 1);
    EXPECT_LT(sl.max_err_yz, 0.01);
}

TEST(PriorWeight, ReportedStdKeepsItsSignFromWhereTheAxisWasLastHeld) {
    // The same 1 cm growth over a 0.5 m frame: where the scan held x this frame (D = 0) it is the
    // frame's std; 10 m after the last hold, summed over the frames since, the variance must be
    // the growth of a drift's (rate D)^2, not of a sum of independent 1 cm steps.
    ActiveFusionParams ap;
    Mat6d c0 = Mat6d::Zero(), c1 = Mat6d::Zero();
    c0.diagonal() << Vec3d::Constant(0.10 * 0.10), Vec3d::Constant(1e-6);
    c1.diagonal() << Vec3d::Constant(0.11 * 0.11), Vec3d::Constant(1e-6 + 1e-12);
    Vec6d since = Vec6d::Zero();
    since[1] = 10.0;
    const Vec6d s = odomIncrementSigmaKeepingSign(c0, c1, ap, 0.5, since);
    EXPECT_NEAR(s[0], 0.01, 1e-12);
    EXPECT_NEAR(s[1], 0.01 * std::sqrt(1.0 + 2.0 * 10.0 / 0.5), 1e-12);
    EXPECT_NEAR(s[5], odomIncrementSigma(c0, c1, ap)[5], 1e-15);  // rotation as before
    // Frame by frame over a blind stretch: the variances add up to (rate L)^2, rate 2 cm/m.
    double sum = 0, D = 0;
    for (int i = 0; i < 40; ++i, D += 0.5) {
        since[0] = D;
        sum += std::pow(odomIncrementSigmaKeepingSign(c0, c1, ap, 0.5, since)[0], 2);
    }
    EXPECT_NEAR(std::sqrt(sum), 0.02 * 20.0, 1e-9);
    // No growth reported (a constant covariance): the floor, whatever D.
    EXPECT_NEAR(odomIncrementSigmaKeepingSign(c1, c1, ap, 0.5, since)[0], ap.odom_sigma_min_xyz, 1e-15);
}

TEST(PriorWeight, CapByOdomAltCovariance) {
    // odom_alt reports an accumulated drift bound: std 0.10 m at t_prev, 0.11 m at t_cur -> the
    // frame's std is 1 cm (information 1e4); rotation grows by less than the 0.01 deg floor.
    ActiveFusionParams ap;
    Mat6d c0 = Mat6d::Zero(), c1 = Mat6d::Zero();
    c0.diagonal() << Vec3d::Constant(0.10 * 0.10), Vec3d::Constant(1e-6);
    c1.diagonal() << Vec3d::Constant(0.11 * 0.11), Vec3d::Constant(1e-6 + 1e-12);
    const Vec6d sigma = odomIncrementSigma(c0, c1, ap);
    EXPECT_NEAR(sigma[0], 0.01, 1e-12);
    EXPECT_NEAR(sigma[5], 0.01 * kDeg, 1e-12);  // floored
    // Shrinking covariance (a reset) gives the floor, not a negative std.
    EXPECT_NEAR(odomIncrementSigma(c1, c0, ap)[0], ap.odom_sigma_min_xyz, 1e-12);
    Vec6d s;
    s << 1e5, 1e3, 1e5, 1e9, 1e9, 10;
    const Vec6d capped = capScale(s, sigma);
    EXPECT_NEAR(capped[0], 1e4, 1e-6);  // capped by odom_alt's 1 cm
    EXPECT_EQ(capped[1], 1e3);          // the scan scale is already lower
    EXPECT_NEAR(capped[3], 1 / std::pow(0.01 * kDeg, 2), 1e-3);
    EXPECT_EQ(capped[5], 10);
}

TEST(ActiveFusion, PaperPriorsWorthForTheCovarianceIsCappedByThePassiveStd) {
    // superloc_paper weighs odom_alt in the solve by the scan's own information (W = (1 - gamma)
    // s); the pose's covariance takes it at no more than the passive prior's per-frame std, else a
    // blind axis reports the scan's millimetres while odom_alt drifts metres (the wander sweep:
    // `ok` while > 0.5 m off).
    ActiveFusionParams ap;
    const localization::OdomFusionPaper paper(ap);
    std::vector<Correspondence> corr;
    localization::FusionFrame f;
    f.corr = &corr;
    f.odom_delta = SE3d::Identity();
    f.scan_H = 1e6 * Mat6d::Identity();  // a stiff scan: s = 1e6 on every axis
    risk::RiskReport r;
    r.gamma << 0.0, 0.5, 1, 1, 1, 1;  // x unconstrained, y half
    const auto p = paper.prior(f, r);
    ASSERT_TRUE(p.has_value());
    ASSERT_TRUE(p->worth.has_value());
    EXPECT_NEAR(p->sqrt_info(0, 0), 1e3, 1e-6);              // the solve: W_x = s
    EXPECT_NEAR(p->sqrt_info(1, 1), std::sqrt(0.5e6), 1e-6);  // W_y = 0.5 s
    const Vec6d passive = passiveInformation(ap);
    EXPECT_NEAR((*p->worth)(0, 0), passive[0], 1e-9);  // the covariance: 2 cm per frame
    EXPECT_NEAR((*p->worth)(1, 1), passive[1], 1e-9);
    EXPECT_EQ((*p->worth)(2, 2), 0.0);  // held by the scan: no prior
    // A weight below the passive one is kept as it is.
    f.scan_H = 100.0 * Mat6d::Identity();
    const auto q = paper.prior(f, r);
    ASSERT_TRUE(q && q->worth);
    EXPECT_NEAR((*q->worth)(0, 0), 100.0, 1e-9);
}
