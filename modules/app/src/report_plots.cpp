#include <superloc/app/report_plots.h>
#include <superloc/app/svg_plot.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace superloc::app {

std::string trajectoryTopViewSvg(const Trajectory& gt, const Trajectory& est,
                                 const std::vector<double>& min_trans_gamma,
                                 const std::string& title) {
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    for (const Trajectory* tr : {&gt, &est})
        for (const auto& p : *tr) {
            const Vec3d t = p.pose.translation();
            if (!t.allFinite()) continue;
            x0 = std::min(x0, t.x()), x1 = std::max(x1, t.x());
            y0 = std::min(y0, t.y()), y1 = std::max(y1, t.y());
        }
    if (!std::isfinite(x0)) x0 = y0 = 0, x1 = y1 = 1;
    const double pad = 0.05 * std::max({x1 - x0, y1 - y0, 1.0});
    SvgPlot plot(640, 560, title);
    plot.setRange(x0 - pad, x1 + pad, y0 - pad, y1 + pad, true);
    plot.axes("x [m]", "y [m]");
    std::vector<double> gx, gy;
    for (const auto& p : gt)
        gx.push_back(p.pose.translation().x()), gy.push_back(p.pose.translation().y());
    plot.polyline(gx, gy, "#9a9a9a", 3.0);
    const bool coloured = min_trans_gamma.size() == est.size();
    for (size_t i = 1; i < est.size(); ++i) {
        const Vec3d a = est[i - 1].pose.translation(), b = est[i].pose.translation();
        plot.segment(
            a.x(), a.y(), b.x(), b.y(),
            coloured ? (std::isfinite(min_trans_gamma[i]) ? gammaColor(min_trans_gamma[i]) : "#444")
                     : "#1f77b4",
            1.8);
    }
    if (coloured)
        plot.legend({{"ground truth", "#9a9a9a"},
                     {"min γ_xyz = 0", gammaColor(0)},
                     {"min γ_xyz = 0.5", gammaColor(0.5)},
                     {"min γ_xyz = 1", gammaColor(1)}});
    else
        plot.legend({{"ground truth", "#9a9a9a"}, {"estimate", "#1f77b4"}});
    return plot.str();
}

std::string gammaTimelineSvg(const eval::FrameLog& log, double threshold, const std::string& title) {
    std::vector<SvgPlot> panels;
    const double t0 = log.frames.empty() ? 0 : log.frames.front().t;
    const double t1 = log.frames.empty() ? 1 : log.frames.back().t;
    std::vector<double> ts;
    for (const auto& f : log.frames) ts.push_back(f.t - t0);
    const double half = halfFramePeriod(ts);  // the shaded span of one flagged frame
    for (int k = 0; k < 6; ++k) {
        SvgPlot p(720, k == 5 ? 130 : 110,
                  k == 0 ? title + " — " + kAxisNames[k] : std::string(kAxisNames[k]));
        p.setRange(0, std::max(t1 - t0, 1e-3), 0, 1.05);
        std::vector<double> g;
        for (size_t i = 0; i < log.frames.size(); ++i) {
            g.push_back(log.frames[i].gamma[k]);
            if (log.frames[i].degenerate[k]) p.spanX(ts[i] - half, ts[i] + half, "#d62728", 0.25);
        }
        p.axes(k == 5 ? "time since first frame [s]" : "", "γ");
        p.hline(threshold, "#d62728");
        p.polyline(ts, g, seriesColor(static_cast<size_t>(k)), 1.4);
        panels.push_back(p);
    }
    return stackSvg(panels);
}

std::string neesTimelineSvg(const eval::Consistency& c, const std::string& title) {
    std::vector<SvgPlot> panels;
    const double t0 = c.t.empty() ? 0 : c.t.front();
    const double t1 = c.t.empty() ? 1 : c.t.back();
    std::vector<double> ts;
    for (double t : c.t) ts.push_back(t - t0);
    const struct {
        const std::vector<double>* v;
        const char* name;
        double dof, bound;
    } rows[3] = {{&c.pos, "position (3 dof)", 3, eval::kChi2_3dof_95},
                 {&c.rot, "rotation (3 dof)", 3, eval::kChi2_3dof_95},
                 {&c.pose, "pose (6 dof)", 6, eval::kChi2_6dof_95}};
    for (int k = 0; k < 3; ++k) {
        if (rows[k].v->empty()) continue;
        SvgPlot p(720, 170, k == 0 ? title + " — NEES, " + rows[k].name : std::string("NEES, ") + rows[k].name);
        // log10 of NEES from 1e-3 to 1e3: a consistent run sits around the dof line.
        p.setRange(0, std::max(t1 - t0, 1e-3), -3, 3);
        std::vector<double> y;
        for (double v : *rows[k].v) y.push_back(std::clamp(std::log10(std::max(v, 1e-6)), -3.0, 3.0));
        p.axes("time since first frame [s]", "log10 NEES",
               {{-2, "0.01"}, {-1, "0.1"}, {0, "1"}, {1, "10"}, {2, "100"}, {3, "1000"}});
        p.hline(std::log10(rows[k].dof), "#2ca02c");
        p.hline(std::log10(rows[k].bound), "#d62728");
        p.polyline(ts, y, seriesColor(static_cast<size_t>(k)), 1.0);
        p.legend({{"dof (consistent mean)", "#2ca02c"}, {"chi-square 95 %", "#d62728"}});
        panels.push_back(p);
    }
    return stackSvg(panels);
}

std::string f1CurvesSvg(const std::vector<std::pair<std::string, eval::RobustnessCurve>>& curves,
                        bool rotation, const std::string& title) {
    SvgPlot plot(640, 400, title);
    plot.setRange(0, 1, 0, 1.05);
    plot.axes(std::string("strictness T (τ = exp(-10 T) ") + (rotation ? "rad)" : "m)"), "F1");
    std::vector<std::pair<std::string, std::string>> legend;
    for (size_t i = 0; i < curves.size(); ++i) {
        const auto& c = curves[i].second.curve;
        std::vector<double> xs, ys;
        for (const auto& p : c) xs.push_back(-std::log(p.tau) / 10.0), ys.push_back(p.f1);
        plot.polyline(xs, ys, seriesColor(i), 2.0);
        char buf[64];
        std::snprintf(buf, sizeof buf, " (%s=%.3f)", rotation ? "Rr" : "Rp", curves[i].second.area);
        legend.emplace_back(curves[i].first + buf, seriesColor(i));
    }
    plot.legend(legend);
    return plot.str();
}

std::vector<double> minTranslationGamma(const Trajectory& traj, const eval::FrameLog& log,
                                        double tolerance) {
    std::vector<double> out(traj.size(), std::numeric_limits<double>::quiet_NaN());
    for (size_t i = 0; i < traj.size(); ++i) {
        const auto it = std::lower_bound(log.frames.begin(), log.frames.end(), traj[i].t,
                                         [](const eval::FrameRecord& f, double t) { return f.t < t; });
        double best = tolerance;
        for (auto c : {it, it == log.frames.begin() ? log.frames.end() : std::prev(it)})
            if (c != log.frames.end() && std::abs(c->t - traj[i].t) <= best) {
                best = std::abs(c->t - traj[i].t);
                out[i] = c->gamma.head<3>().minCoeff();
            }
    }
    return out;
}

double halfFramePeriod(const std::vector<double>& ts) {
    std::vector<double> dts;
    for (size_t i = 1; i < ts.size(); ++i) dts.push_back(ts[i] - ts[i - 1]);
    std::sort(dts.begin(), dts.end());
    return dts.empty() ? 0.05 : 0.5 * dts[dts.size() / 2];
}

void writeTextFile(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error(path + ": cannot open for writing");
    out << text;
    if (!out.flush()) throw std::runtime_error(path + ": write failed");
}

}  // namespace superloc::app
