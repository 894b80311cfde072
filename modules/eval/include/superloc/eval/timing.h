// Runtime statistics (DESIGN §8) of per-frame wall times.
#pragma once

#include <cstddef>
#include <vector>

namespace superloc::eval {

struct TimingStats {
    size_t frames = 0;
    double mean_ms = 0, median_ms = 0, p95_ms = 0, max_ms = 0;
    double fps = 0;  ///< 1000 / mean_ms: frames per second of processing
};

/// Statistics of per-frame times [ms]; p95 is the nearest-rank 95th percentile
/// (sorted[ceil(0.95 n) - 1]). All zero for an empty list.
TimingStats timingStats(std::vector<double> ms);

}  // namespace superloc::eval
