// The evaluation's pictures (doc/evaluation.md), as SVG text.
#pragma once

#include <superloc/core/types.h>
#include <superloc/eval/evaluation.h>
#include <superloc/eval/frame_log.h>
#include <superloc/eval/robustness.h>

#include <string>
#include <utility>
#include <vector>

namespace superloc::app {

/// Top view (x, y) of the ground truth (grey) and an estimate; each estimate step is coloured by
/// its frame's min(gamma_x, gamma_y, gamma_z) (red 0 .. green 1) when `min_trans_gamma` has one
/// value per estimate pose, else drawn blue.
std::string trajectoryTopViewSvg(const Trajectory& gt, const Trajectory& est,
                                 const std::vector<double>& min_trans_gamma,
                                 const std::string& title);

/// Gamma per axis over time: six stacked panels, the degenerate threshold dashed, the frames the
/// localizer flagged degenerate on that axis shaded.
std::string gammaTimelineSvg(const eval::FrameLog& log, double threshold, const std::string& title);
/// NEES per frame over time (position, rotation, the full pose when known) on a log scale, with
/// the dof (a consistent average) and the chi-square 95 % bound (eval::Consistency).
std::string neesTimelineSvg(const eval::Consistency& c, const std::string& title);

/// F1(tau) curves of several runs against the strictness T (tau = exp(-10 T)); `rotation` only
/// changes the axis label. Each entry: (name, curve).
std::string f1CurvesSvg(const std::vector<std::pair<std::string, eval::RobustnessCurve>>& curves,
                        bool rotation, const std::string& title);

/// min(gamma_x, gamma_y, gamma_z) of the frame-log record nearest in time to each pose of
/// `traj` (within `tolerance` s, else NaN).
std::vector<double> minTranslationGamma(const Trajectory& traj, const eval::FrameLog& log,
                                        double tolerance);

/// Half the median step of increasing times `ts` [s] (0.05 with fewer than two): the span drawn
/// for one frame on a timeline.
double halfFramePeriod(const std::vector<double>& ts);

/// Writes text to a file; throws std::runtime_error naming the file on failure.
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace superloc::app
