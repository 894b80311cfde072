// Cost of superloc's prior weighting per frame (doc/method.md §2): the scan information H of the
// frame's correspondences (body coordinates), s_k, W = diag(max(0, 1 - gamma)) s, and Zhang's
// eigen remap — the work added to the risk step. Synthetic box-room correspondences.
// And the IMU window's solve with and without its marginal (doc/method.md §3), and the whole
// per-frame work of superloc's risk and weighting (doc/method.md §2).
#include <benchmark/benchmark.h>
#include <superloc/core/se3.h>
#include <superloc/fusion/estimate_information.h>
#include <superloc/fusion/pose_posterior.h>
#include <superloc/fusion/frame_problem.h>
#include <superloc/fusion/odom_calibration.h>
#include <superloc/risk/alignment_risk.h>
#include <superloc/fusion/prior_weight.h>

#include <random>

using namespace superloc;
using namespace superloc::fusion;

namespace {
std::vector<Correspondence> room(int n) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Correspondence> out(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
        auto& c = out[static_cast<size_t>(i)];
        const int axis = i % 3;
        c.n = Vec3d::Unit(axis);
        c.p = Vec3d(8 * u(rng), 6 * u(rng), 1.5 * u(rng));
        c.p[axis] = axis == 2 ? -1.5 : 6.0;
        c.q = c.p;
        c.weight = 0.5 + 0.5 * std::abs(u(rng));
    }
    return out;
}
}  // namespace

static void BM_ActivePriorWeight(benchmark::State& st) {
    const auto corr = room(static_cast<int>(st.range(0)));
    const SE3d T = makePoseRPY(1, 2, 0.5, 0.01, 0.02, 0.3);
    Vec6d gamma;
    gamma << 0.05, 1, 1, 0.9, 1, 1;
    for (auto _ : st) {
        const Mat6d H = scanInformation(corr, T, 0.05);
        benchmark::DoNotOptimize(activeInformation(gamma, priorScale(H)));
    }
}
BENCHMARK(BM_ActivePriorWeight)->Arg(500)->Arg(2000);

static void BM_EigenRemap(benchmark::State& st) {
    const auto corr = room(2000);
    const SE3d T = makePoseRPY(1, 2, 0.5, 0.01, 0.02, 0.3);
    const Mat6d H = scanInformation(corr, T, 1.0) / 2000.0;
    const SE3d T2 = T * makePoseRPY(0.1, 0.01, 0, 0, 0, 0.001);
    for (auto _ : st) benchmark::DoNotOptimize(eigenRemap(T, T2, H, 0.05));
}
BENCHMARK(BM_EigenRemap);

// One solve of the two-state IMU window (scan factor over N correspondences, IMU factor over
// 0.1 s at 200 Hz, the previous state's prior), with Arg(1) also computing the marginal of the
// current state (Jacobian evaluation, 30 x 30 information, Schur complement) as every solve
// of the default configuration does.
static void BM_ImuWindowSolve(benchmark::State& st) {
    const auto corr = room(2000);
    imu::Preintegration pre(imu::ImuBias{}, imu::ImuNoise{0.02, 0.002});
    for (int k = 0; k < 20; ++k) pre.integrate(Vec3d(0.2, 0, 9.81), Vec3d(0, 0, 0.1), 0.005);
    FusionParams params;
    for (auto _ : st) {
        st.PauseTiming();
        ScanFactor scan(corr, 0.05);
        FrameState prev, cur;
        cur.setPose(makePoseRPY(0.01, -0.01, 0.005, 0.001, 0, 0.002));
        FrameProblemInputs in;
        in.prev = &prev;
        in.cur = &cur;
        in.scan = &scan;
        in.imu = &pre;
        in.marginalize = st.range(0) != 0;
        st.ResumeTiming();
        benchmark::DoNotOptimize(solveFrame(in, params));
    }
}
BENCHMARK(BM_ImuWindowSolve)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// Everything superloc adds per frame before and after its solve (doc/method.md §2), as the
// localizer runs it: the paper's risk (labels, gamma, flags, eigen diagnostics) of 2000
// correspondences; their scan information H and its noise floor; the estimate's information
// carried through 0.1 s of IMU (one Jacobian evaluation of the IMU factor and the previous
// state's prior, a Schur complement); where the estimate and the scan alone are weak; odom_alt
// corrected and weighed by its calibration; W = G diag(1/sigma^2) G and its square root; then,
// after the solve, the calibration's update and the information's commit.
static void BM_RiskAndWeight(benchmark::State& st) {
    const auto corr = room(2000);
    const SE3d T = makePoseRPY(1, 2, 0.5, 0.01, 0.02, 0.3);
    imu::Preintegration pre(imu::ImuBias{}, imu::ImuNoise{0.02, 0.002});
    for (int k = 0; k < 20; ++k) pre.integrate(Vec3d(0.2, 0, 9.81), Vec3d(0, 0, 0.1), 0.005);
    FusionParams params;
    risk::RiskParams rp;
    FrameState prev, cur;
    cur.setPose(T);
    prev.setPose(T * makePoseRPY(-0.5, 0, 0, 0, 0, -0.01));
    EstimateInformation est;
    OdomCalibration calib;
    const SE3d odom = makePoseRPY(0.51, 0.002, 0, 0, 0, 0.0101);
    std::array<bool, 6> held{};
    held.fill(true);
    for (int k = 0; k < 200; ++k) calib.update(odom, makePoseRPY(0.5, 0, 0, 0, 0, 0.01), held);
    // Then x blind (a corridor): its correction's share and worth are taken beyond the longest
    // block of held travel measured, the costliest path.
    std::array<bool, 6> blind = held;
    blind[0] = false;
    Vec6d weak;
    weak << Vec3d::Constant(0.05), Vec3d::Constant(0.5 * M_PI / 180);
    for (auto _ : st) {
        benchmark::DoNotOptimize(risk::computeAlignmentRisk(corr, T, Vec3d(0, 0, 0.15), rp));
        FrameState p = prev, c = cur;
        FrameProblemInputs in;
        in.prev = &p;
        in.cur = &c;
        in.imu = &pre;
        est.predict(in, params);
        const Mat6d H = informationAboveNoise(scanInformation(corr, T, 0.05), 0.0049);
        const Weakness scan = weakness(H, weak), e = weakness(est.information(H), weak);
        const SE3d delta = calib.correct(odom);
        const Vec6d w = calib.sigma(odom).cwiseAbs2().cwiseInverse();
        benchmark::DoNotOptimize(sqrtInfo(Mat6d(e.G * w.asDiagonal() * e.G)));
        benchmark::DoNotOptimize(est.motionVariance(0.1, T.linear()));  // the innovation test
        benchmark::DoNotOptimize(delta);
        benchmark::DoNotOptimize(scan);
        calib.update(odom, makePoseRPY(0.5, 0, 0, 0, 0, 0.01), blind);
        est.commit(cur, H);
    }
}
BENCHMARK(BM_RiskAndWeight)->Unit(benchmark::kMicrosecond);

// The reported pose's covariance per tracked frame (fusion::PosePosterior, doc/method.md §4): the
// last frame's information carried through the IMU factor and odom_alt's prior, the scan added,
// the covariance, the commit; and the scan-only covariance every frame gets first.
static void BM_PoseCovariance(benchmark::State& st) {
    const auto corr = room(2000);
    const SE3d T = makePoseRPY(1, 2, 0.5, 0.01, 0.02, 0.3);
    imu::Preintegration pre(imu::ImuBias{}, imu::ImuNoise{0.004, 0.0004});
    for (int k = 0; k < 20; ++k) pre.integrate(Vec3d(0.2, 0, 9.81), Vec3d(0, 0, 0.1), 0.005);
    FusionParams params;
    FrameState prev, cur;
    cur.setPose(T);
    prev.setPose(T * makePoseRPY(-0.5, 0, 0, 0, 0, -0.01));
    PosePosterior post(Vec6d::Constant(0.01), 0.005);
    RelativePosePrior prior;
    prior.delta = prev.T_map_imu().inverse() * cur.T_map_imu();
    prior.sqrt_info = Mat6d::Identity() * 100;
    for (auto _ : st) {
        const Mat6d H = informationAboveNoise(scanInformation(corr, T, 0.05), 0.0049);
        benchmark::DoNotOptimize(post.covariance(H, FloorGeometry{H}));
        FrameState p = prev, c = cur;
        FrameProblemInputs in;
        in.prev = &p;
        in.cur = &c;
        in.imu = &pre;
        in.prior = prior;
        const auto u = post.update(in, params, H, FloorGeometry{H});
        post.commit(u);
        benchmark::DoNotOptimize(u.cov);
    }
}
BENCHMARK(BM_PoseCovariance)->Unit(benchmark::kMicrosecond);

// What a frame deskewed without the IMU adds to BM_PoseCovariance: the sweep's departure through
// the scan's geometry and its points' times (doc/method.md §4 "The sweep"), 2000 correspondences.
static void BM_SweepCovariance(benchmark::State& st) {
    auto corr = room(2000);
    for (size_t i = 0; i < corr.size(); ++i) corr[i].rel_time = -0.1f * float(i) / float(corr.size());
    const SE3d T = makePoseRPY(1, 2, 0.5, 0.01, 0.02, 0.3);
    SweepDeparture d;
    d.delta << 0.002, 0.001, 0.001, 0.0005, 0.002, 0.001;
    d.T = 0.1;
    d.parabola = true;
    const Mat6d carried = Mat6d::Identity() * 100;
    for (auto _ : st) benchmark::DoNotOptimize(sweepCovariance(corr, T, d, 0.05, 0.0049, carried));
}
BENCHMARK(BM_SweepCovariance)->Unit(benchmark::kMicrosecond);

// The share of the map's error the position takes (fusion::mapErrorShare, doc/method.md §4), per
// tracked frame: 2 000 correspondences in a 16 x 12 m room (a few dozen 4 m cells), and spread
// over a 200 m square of open ground (more than the 128 cells' cap: the grid is coarsened).
static void BM_MapErrorShare(benchmark::State& st) {
    auto corr = room(2000);
    if (st.range(0) == 1) {
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u(-100, 100);
        for (auto& c : corr) c.q = Vec3d(u(rng), u(rng), c.q.z());
    }
    const SE3d T = makePoseRPY(1, 2, 0.5, 0.01, 0.02, 0.3);
    for (auto _ : st) benchmark::DoNotOptimize(mapErrorShare(corr, T, 4.0, 10.0, 0.0049));
}
BENCHMARK(BM_MapErrorShare)->ArgName("open")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
