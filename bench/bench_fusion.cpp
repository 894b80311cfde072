// Cost of superloc's prior weighting per frame (doc/method.md §2): the scan information H of the
// frame's correspondences (body coordinates), s_k, W = diag(max(0, 1 - gamma)) s, and Zhang's
// eigen remap — the work added to the risk step. Synthetic box-room correspondences.
#include <benchmark/benchmark.h>
#include <superloc/core/se3.h>
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

BENCHMARK_MAIN();
