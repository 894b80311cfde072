#include <superloc/eval/robustness.h>

#include <algorithm>
#include <cmath>

namespace superloc::eval {

F1Point f1At(const std::vector<double>& errors, size_t gt_steps, double tau) {
    F1Point p;
    p.tau = tau;
    size_t inliers = 0;
    for (double e : errors)
        if (e <= tau) ++inliers;  // NaN compares false: an unjudged step is never an inlier
    p.precision = errors.empty() ? 0.0 : double(inliers) / double(errors.size());
    p.recall = gt_steps == 0 ? 0.0 : std::min(1.0, double(inliers) / double(gt_steps));
    const double s = p.precision + p.recall;
    p.f1 = s > 0 ? 2 * p.precision * p.recall / s : 0.0;
    return p;
}

RobustnessCurve robustnessArea(const std::vector<double>& errors, size_t gt_steps, int bins) {
    RobustnessCurve r;
    bins = std::max(1, bins);
    const double h = 1.0 / bins;
    for (int k = 0; k < bins; ++k) {
        // tau = exp(-10 T): bin [k h, (k+1) h] in T is tau in [exp(-10 (k+1) h), exp(-10 k h)].
        const double width = std::exp(-10.0 * k * h) - std::exp(-10.0 * (k + 1) * h);
        const F1Point p = f1At(errors, gt_steps, std::exp(-10.0 * (k + 0.5) * h));
        r.area += p.f1 * width;
        r.curve.push_back(p);
    }
    return r;
}

}  // namespace superloc::eval
