// Robustness metrics of SubT-MRS (Zhao et al., CVPR 2024; paper §IV-C; doc/evaluation.md).
//
// A frame i >= 1 of the estimate is an inlier at threshold tau when its RPE step error
// (i-1 -> i) is <= tau. precision = inliers / estimated steps, recall = inliers / GT steps
// (a run that stops early loses recall), F1 their harmonic mean. Rp (translation errors, m) and
// Rr (rotation errors, rad) are the area under F1(tau) for tau in (0, 1], sampled through
// tau = exp(-10 T): see doc/evaluation.md for the exact integration.
#pragma once

#include <cstddef>
#include <vector>

namespace superloc::eval {

struct F1Point {
    double tau = 0;  ///< threshold [m] or [rad]
    double precision = 0, recall = 0, f1 = 0;
};

/// F1 at one threshold. `errors` has one entry per estimated step (NaN = not judged, never an
/// inlier); `gt_steps` = GT frames - 1.
F1Point f1At(const std::vector<double>& errors, size_t gt_steps, double tau);

struct RobustnessCurve {
    double area = 0;             ///< Rp or Rr, in [0, 1 - exp(-10)]
    std::vector<F1Point> curve;  ///< one point per bin, tau decreasing (T increasing)
};

/// Area under F1(tau) for tau in [exp(-10), 1]: T in [0, 1] is cut into `bins` equal bins; bin
/// [T_a, T_b] covers tau in [exp(-10 T_b), exp(-10 T_a)] and contributes F1(tau(T_mid)) times
/// that width (midpoint rule in T, exact widths in tau).
RobustnessCurve robustnessArea(const std::vector<double>& errors, size_t gt_steps, int bins);

}  // namespace superloc::eval
