#include <superloc/eval/timing.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace superloc::eval {

TimingStats timingStats(std::vector<double> ms) {
    TimingStats s;
    s.frames = ms.size();
    if (ms.empty()) return s;
    std::sort(ms.begin(), ms.end());
    const size_t n = ms.size();
    s.mean_ms = std::accumulate(ms.begin(), ms.end(), 0.0) / double(n);
    s.median_ms = n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
    const size_t rank = static_cast<size_t>(std::ceil(0.95 * double(n)));
    s.p95_ms = ms[std::max<size_t>(rank, 1) - 1];
    s.max_ms = ms.back();
    s.fps = s.mean_ms > 0 ? 1000.0 / s.mean_ms : 0.0;
    return s;
}

}  // namespace superloc::eval
