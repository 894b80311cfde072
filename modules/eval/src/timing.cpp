#include <superloc/eval/timing.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace superloc::eval {

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t rank = static_cast<size_t>(std::ceil(q * double(v.size())));
    return v[std::min(std::max<size_t>(rank, 1), v.size()) - 1];
}

TimingStats timingStats(std::vector<double> ms) {
    TimingStats s;
    s.frames = ms.size();
    if (ms.empty()) return s;
    const size_t n = ms.size();
    s.mean_ms = std::accumulate(ms.begin(), ms.end(), 0.0) / double(n);
    s.median_ms = median(ms);
    s.p95_ms = percentile(ms, 0.95);
    s.max_ms = *std::max_element(ms.begin(), ms.end());
    s.fps = s.mean_ms > 0 ? 1000.0 / s.mean_ms : 0.0;
    return s;
}

}  // namespace superloc::eval
