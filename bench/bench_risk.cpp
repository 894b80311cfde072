// Cost of the risk step (doc/method.md §1) for one frame of ~2000 point-to-plane correspondences
// (a ray-cast corridor, as the localizer would feed it). Issue 5 asks for <= 1 ms per frame.
#include <benchmark/benchmark.h>
#include <superloc/risk/alignment_risk.h>

#include <cmath>
#include <random>

using namespace superloc;
using namespace superloc::risk;

namespace {
/// n correspondences on the walls (y = +-1.5), floor and ceiling (z = +-1.3) of a corridor along
/// x, points up to 20 m ahead and behind, fit weights in [0.5, 1].
std::vector<Correspondence> corridor(size_t n) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> along(-20, 20), across(-1.5, 1.5), w(0.5, 1.0);
    std::vector<Correspondence> out(n);
    for (size_t i = 0; i < n; ++i) {
        Correspondence& c = out[i];
        const double x = along(rng), s = across(rng);
        switch (i % 4) {
            case 0:
                c.p = {x, 1.5, s}, c.n = {0, -1, 0};
                break;
            case 1:
                c.p = {x, -1.5, s}, c.n = {0, 1, 0};
                break;
            case 2:
                c.p = {x, s, -1.3}, c.n = {0, 0, 1};
                break;
            default:
                c.p = {x, s, 1.3}, c.n = {0, 0, -1};
                break;
        }
        c.weight = w(rng);
    }
    return out;
}

void BM_AlignmentRisk(benchmark::State& state) {
    const auto cs = corridor(static_cast<size_t>(state.range(0)));
    RiskParams params;
    params.hessian_eigen = state.range(1) != 0;
    for (auto _ : state) {
        RiskReport r = computeAlignmentRisk(cs, params);
        benchmark::DoNotOptimize(r.gamma.data());
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}
}  // namespace

BENCHMARK(BM_AlignmentRisk)
    ->ArgsProduct({{500, 2000, 8000}, {0, 1}})
    ->ArgNames({"correspondences", "hessian"})
    ->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
