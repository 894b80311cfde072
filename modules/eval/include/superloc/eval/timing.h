// Runtime statistics (doc/evaluation.md) of per-frame wall times.
#pragma once

#include <cstddef>
#include <vector>

namespace superloc::eval {

struct TimingStats {
    size_t frames = 0;
    double mean_ms = 0, median_ms = 0, p95_ms = 0, max_ms = 0;
    double fps = 0;  ///< 1000 / mean_ms: frames per second of processing
};

/// The project's one set of timing statistics (superloc-localize's summary.json, superloc-eval,
/// the bench tables and the micro-benchmarks all use these).
/// Median of the values: the middle one, or the mean of the two middle ones; 0 when empty.
double median(std::vector<double> v);
/// Nearest-rank q-quantile, q in (0, 1]: sorted[ceil(q n) - 1]; 0 when empty.
double percentile(std::vector<double> v, double q);
/// Statistics of per-frame times [ms]: median(), p95 = percentile(0.95). All zero for an empty list.
TimingStats timingStats(std::vector<double> ms);

}  // namespace superloc::eval
