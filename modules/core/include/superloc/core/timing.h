// Wall-clock helpers for the per-stage timings of reports (StageTimes, relocalization).
#pragma once

#include <chrono>

namespace superloc {

using SteadyClock = std::chrono::steady_clock;

/// Milliseconds elapsed since `t0`.
inline double msSince(SteadyClock::time_point t0) {
    return std::chrono::duration<double, std::milli>(SteadyClock::now() - t0).count();
}

}  // namespace superloc
