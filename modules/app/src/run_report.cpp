#include <superloc/core/se3.h>
#include <superloc/fusion/pose_posterior.h>
#include <superloc/app/report_plots.h>
#include <superloc/app/run_report.h>

#include <superloc/app/svg_plot.h>
#include <superloc/eval/timing.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace superloc::app {
namespace {

const char* const kHealthName[3] = {"ok", "degraded", "lost"};
const char* const kHealthColor[3] = {"#2ca02c", "#ff7f0e", "#d62728"};
constexpr double kWidth = 820;       ///< [px] of every figure
constexpr size_t kMaxMapDots = 30000;   ///< map points drawn at most (about 15 bytes each)
constexpr size_t kMaxLinePoints = 3000; ///< points of a time series drawn at most

/// A position the plots can show (a lost frame may be reported 1e300 m away).
bool drawable(double v) { return std::isfinite(v) && std::abs(v) < 1e7; }

std::string number(double v) {
    char buf[40];
    if (std::isfinite(v) && v == std::round(v) && std::abs(v) < 1e15)
        std::snprintf(buf, sizeof buf, "%.0f", v);
    else
        std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

/// A long series thinned to at most `max_points`: per group of consecutive frames its smallest
/// and largest value in time order, so that spikes stay visible. NaN values (no value) are left
/// out of a group; a group with none is a NaN (a gap in the line).
void thin(const std::vector<double>& ts, const std::vector<double>& vs, size_t max_points,
          std::vector<double>& to, std::vector<double>& vo) {
    to.clear(), vo.clear();
    const size_t n = std::min(ts.size(), vs.size());
    if (n <= max_points) {
        to.assign(ts.begin(), ts.begin() + static_cast<std::ptrdiff_t>(n));
        vo.assign(vs.begin(), vs.begin() + static_cast<std::ptrdiff_t>(n));
        return;
    }
    const size_t group = (2 * n + max_points - 1) / max_points;
    for (size_t a = 0; a < n; a += group) {
        const size_t b = std::min(n, a + group);
        size_t lo = b, hi = b;
        for (size_t i = a; i < b; ++i) {
            if (!std::isfinite(vs[i])) continue;
            if (lo == b || vs[i] < vs[lo]) lo = i;
            if (hi == b || vs[i] > vs[hi]) hi = i;
        }
        if (lo == b) {
            to.push_back(ts[a]), vo.push_back(std::numeric_limits<double>::quiet_NaN());
            continue;
        }
        for (size_t i : {std::min(lo, hi), std::max(lo, hi)}) to.push_back(ts[i]), vo.push_back(vs[i]);
    }
}

/// Bars of one row of the timeline, bounded in number for any run: the row is cut into columns
/// of about a pixel, each frame marks the columns its span (t ± half) covers with its rank (0:
/// nothing to show), a column shows the highest rank marked (so a lost frame is never hidden by
/// ok ones), and neighbouring columns of one rank make one bar in colors[rank].
template <typename RankOf>
void rowBars(SvgPlot& p, const std::vector<double>& ts, double half, double t0, double t1, double row,
             RankOf rank, const std::vector<std::string>& colors) {
    const size_t n = static_cast<size_t>(kWidth);
    const double w = (t1 - t0) / static_cast<double>(n);
    const auto column = [&](double t) {
        return static_cast<size_t>(std::clamp(std::floor((t - t0) / w), 0.0, static_cast<double>(n - 1)));
    };
    std::vector<int> col(n, 0);
    for (size_t i = 0; i < ts.size(); ++i)
        if (const int r = rank(i); r > 0)
            for (size_t c = column(ts[i] - half); c <= column(ts[i] + half); ++c) col[c] = std::max(col[c], r);
    for (size_t a = 0; a < n;) {
        size_t b = a + 1;
        while (b < n && col[b] == col[a]) ++b;
        if (col[a] > 0)
            p.segment(t0 + static_cast<double>(a) * w, row, t0 + static_cast<double>(b) * w, row,
                      colors[static_cast<size_t>(col[a])], 9);
        a = b;
    }
}

SvgPlot topView(const std::vector<ReportFrame>& frames, const std::vector<double>& mx,
                const std::vector<double>& my, size_t& dots_drawn) {
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    const auto grow = [&](double x, double y) {
        if (!drawable(x) || !drawable(y)) return;
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    };
    for (size_t i = 0; i < mx.size(); ++i) grow(mx[i], my[i]);
    for (const auto& f : frames) grow(f.x, f.y);
    if (!std::isfinite(x0)) x0 = y0 = 0, x1 = y1 = 1;
    const double extent = std::max({x1 - x0, y1 - y0, 1.0}), pad = 0.03 * extent;
    // As tall as the data's aspect needs (a corridor is a strip), within 320..760 px.
    const double aspect = (y1 - y0 + 2 * pad) / std::max(x1 - x0 + 2 * pad, 1e-9);
    SvgPlot plot(kWidth, std::clamp(68 + (kWidth - 75) * aspect, 320.0, 760.0),
                 "Top view: prior map and trajectory by health");
    plot.setRange(x0 - pad, x1 + pad, y0 - pad, y1 + pad, true);
    plot.axes("x [m]", "y [m]");
    dots_drawn = plot.dots(mx, my, "#b4b4b4", 0.8, kMaxMapDots);
    // The trajectory as one line per stretch of one health state, each starting where the last
    // ended; positions closer than 1/2000 of the extent to the last drawn are left out.
    const double step = extent / 2000;
    std::vector<double> xs, ys;
    int state = -1;
    const auto flush = [&] {
        if (xs.size() > 1) plot.polyline(xs, ys, kHealthColor[state], 2.2);
    };
    for (const auto& f : frames) {
        const double x = drawable(f.x) && drawable(f.y) ? f.x : std::nan("");
        const double y = std::isfinite(x) ? f.y : std::nan("");
        if (f.health != state) {
            flush();
            const double lx = xs.empty() ? x : xs.back(), ly = ys.empty() ? y : ys.back();
            xs.assign({lx}), ys.assign({ly});
            state = std::clamp(f.health, 0, 2);
        } else if (std::isfinite(x) && std::isfinite(xs.back()) &&
                   std::hypot(x - xs.back(), y - ys.back()) < step) {
            continue;
        }
        xs.push_back(x), ys.push_back(y);
    }
    flush();
    if (!frames.empty()) plot.dots({frames.front().x}, {frames.front().y}, "#000", 4, 1);
    plot.legend({{"prior map (from above)", "#b4b4b4"},
                 {"ok", kHealthColor[0]},
                 {"degraded", kHealthColor[1]},
                 {"lost", kHealthColor[2]},
                 {"start (black dot)", "#000"}});
    return plot;
}

SvgPlot flagsTimeline(const std::vector<ReportFrame>& frames, const std::vector<double>& ts,
                      double half) {
    const double span = std::max(ts.empty() ? 1.0 : ts.back(), 1e-3);
    SvgPlot p(kWidth, 250, "Health and flagged (degenerate) axes over time");
    p.setRange(-half, span + half, -0.7, 6.7);
    std::vector<std::pair<double, std::string>> rows = {{6, "health"}};
    for (int k = 0; k < 6; ++k) rows.emplace_back(5 - k, kAxisNames[k]);
    p.axes("time since the first frame [s]", "", rows);
    rowBars(p, ts, half, -half, span + half, 6, [&](size_t i) { return std::clamp(frames[i].health, 0, 2) + 1; },
            {"", kHealthColor[0], kHealthColor[1], kHealthColor[2]});
    for (int k = 0; k < 6; ++k)
        rowBars(p, ts, half, -half, span + half, 5 - k, [&](size_t i) { return frames[i].degenerate[k] ? 1 : 0; },
                {"", seriesColor(static_cast<size_t>(k))});
    return p;
}

SvgPlot priorTimeline(const std::vector<ReportFrame>& frames, const std::vector<double>& ts,
                      size_t& values) {
    const double span = std::max(ts.empty() ? 1.0 : ts.back(), 1e-3);
    std::array<std::vector<double>, 6> lw;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    values = 0;
    for (const auto& f : frames)
        for (int k = 0; k < 6; ++k) {
            const double w = f.prior_used && f.prior_w[k] > 0 ? std::log10(f.prior_w[k]) : std::nan("");
            lw[k].push_back(w);
            if (std::isfinite(w)) lo = std::min(lo, w), hi = std::max(hi, w), ++values;
        }
    SvgPlot p(kWidth, 270, "odom_alt prior weight (information) per axis over time");
    if (!std::isfinite(lo)) lo = 0, hi = 1;
    // Room at the top for the legend.
    p.setRange(0, span, std::floor(lo - 0.3), std::ceil(hi + 0.3 + 0.8 * (hi - lo + 0.6)));
    p.axes("time since the first frame [s]", "log10 prior_w");
    std::vector<std::pair<std::string, std::string>> legend;
    std::vector<double> tt, vv;
    for (int k = 0; k < 6; ++k) {
        thin(ts, lw[k], kMaxLinePoints, tt, vv);
        p.polyline(tt, vv, seriesColor(static_cast<size_t>(k)), 1.5);
        // A frame with a prior between two without is no line: a dot.
        std::vector<double> lone_t, lone_v;
        for (size_t i = 0; i < vv.size(); ++i)
            if (std::isfinite(vv[i]) && (i == 0 || !std::isfinite(vv[i - 1])) &&
                (i + 1 == vv.size() || !std::isfinite(vv[i + 1])))
                lone_t.push_back(tt[i]), lone_v.push_back(vv[i]);
        p.dots(lone_t, lone_v, seriesColor(static_cast<size_t>(k)), 1.8, kMaxLinePoints);
        legend.emplace_back(kAxisNames[k], seriesColor(static_cast<size_t>(k)));
    }
    p.legend(legend);
    return p;
}

SvgPlot timingTimeline(const std::vector<ReportFrame>& frames, const std::vector<double>& ts) {
    const double span = std::max(ts.empty() ? 1.0 : ts.back(), 1e-3);
    std::vector<double> ms;
    for (const auto& f : frames) ms.push_back(f.ms);
    const double top = ms.empty() ? 1.0 : *std::max_element(ms.begin(), ms.end());
    const double med = eval::median(ms);
    SvgPlot p(kWidth, 250, "Wall time per frame");
    p.setRange(0, span, 0, std::max(1.05 * top, 1e-3));
    p.axes("time since the first frame [s]", "ms");
    std::vector<double> tt, vv;
    thin(ts, ms, kMaxLinePoints, tt, vv);
    p.polyline(tt, vv, seriesColor(0), 1.2);
    p.hline(med, "#d62728");
    p.legend({{"ms_total", seriesColor(0)}, {"median " + number(med) + " ms", "#d62728"}});
    return p;
}

/// The pose's largest std over time (log scale, 1 mm to 10 m / 0.001 deg to 100 deg).
SvgPlot sigmaTimeline(const std::vector<ReportFrame>& frames, const std::vector<double>& ts) {
    const double span = std::max(ts.empty() ? 1.0 : ts.back(), 1e-3);
    SvgPlot p(kWidth, 250, "The pose's std over time (its covariance's largest, doc/method.md §4)");
    p.setRange(0, span, -3, 2);
    p.axes("time since the first frame [s]", "log10 std",
           {{-3, "0.001"}, {-2, "0.01"}, {-1, "0.1"}, {0, "1"}, {1, "10"}, {2, "100"}});
    std::vector<double> t, xyz, deg;
    for (size_t i = 0; i < frames.size(); ++i) {
        if (!(frames[i].sigma_xyz > 0)) continue;
        t.push_back(ts[i]);
        xyz.push_back(std::clamp(std::log10(frames[i].sigma_xyz), -3.0, 2.0));
        deg.push_back(std::clamp(std::log10(std::max(frames[i].sigma_deg, 1e-6)), -3.0, 2.0));
    }
    std::vector<double> tt, vv;
    thin(t, xyz, kMaxLinePoints, tt, vv);
    p.polyline(tt, vv, seriesColor(0), 1.2);
    thin(t, deg, kMaxLinePoints, tt, vv);
    p.polyline(tt, vv, seriesColor(1), 1.2);
    p.legend({{"position [m]", seriesColor(0)}, {"rotation [deg]", seriesColor(1)}});
    return p;
}

/// summary.json as rows "key.sub = value", in its order.
void flatten(const io::Json& j, const std::string& prefix, std::string& rows) {
    if (j.is_object()) {
        for (const auto& [k, v] : j.items()) flatten(v, prefix.empty() ? k : prefix + "." + k, rows);
        return;
    }
    std::string v;
    if (j.is_null())
        v = "–";
    else if (j.is_string())
        v = j.get<std::string>();
    else if (j.is_number())
        v = number(j.get<double>());
    else
        v = j.dump();
    rows += "<tr><td>" + xmlEscape(prefix) + "</td><td>" + xmlEscape(v) + "</td></tr>\n";
}

std::string figure(const std::string& id, const std::vector<SvgPlot>& plots, const std::string& caption) {
    return "<figure id=\"" + id + "\">\n" + stackSvg(plots, false) + "<figcaption>" + caption +
           "</figcaption>\n</figure>\n";
}

const char* kStyle =
    "body{font-family:sans-serif;margin:20px auto;max-width:860px;color:#222;padding:0 12px}"
    "h1{font-size:20px}h2{font-size:16px;margin-top:28px}"
    "table{border-collapse:collapse;font-size:13px}td{padding:2px 12px 2px 0;"
    "border-bottom:1px solid #e4e4e4;vertical-align:top}td:first-child{color:#555}"
    "figure{margin:18px 0}figcaption{font-size:13px;color:#444;margin-top:4px}"
    ".status{font-size:15px}.failed{color:#b00;font-weight:bold}"
    "#errors{color:#b00;white-space:pre-wrap}#errors:empty{display:none}";

// In <head>: any script error from here on is shown on the page and marks it.
const char* kErrorScript =
    "window.onerror = function (message, source, line) {\n"
    "  var e = document.getElementById('errors');\n"
    "  if (e) e.textContent += 'script error: ' + message + ' (line ' + line + ')\\n';\n"
    "  document.documentElement.setAttribute('data-script-error', String(message));\n"
    "  if (document.body) document.body.setAttribute('data-report', 'error');\n"
    "};\n";

// At the end of <body>: once loaded, every figure must hold a drawing with a size.
const char* kCheckScript =
    "window.addEventListener('load', function () {\n"
    "  var figures = document.querySelectorAll('figure');\n"
    "  for (var i = 0; i < figures.length; ++i) {\n"
    "    var svg = figures[i].querySelector('svg');\n"
    "    if (!svg || !svg.querySelector('polyline, path, line'))\n"
    "      throw new Error('figure ' + figures[i].id + ' has no drawing');\n"
    "    var box = svg.getBBox();\n"
    "    if (!(box.width > 0 && box.height > 0)) throw new Error('figure ' + figures[i].id + ' is empty');\n"
    "  }\n"
    "  if (document.body.getAttribute('data-report') !== 'error')\n"
    "    document.body.setAttribute('data-report', 'drawn ' + figures.length);\n"
    "});\n";

}  // namespace

void RunReport::addMapPoints(const std::vector<Vec3f>& points) {
    if (cell_ <= 0) {
        Vec3f lo = Vec3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
        for (const auto& p : points)
            if (p.allFinite()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        const float extent = hi.x() >= lo.x() ? std::max(hi.x() - lo.x(), hi.y() - lo.y()) : 0.f;
        cell_ = std::max(0.02f, extent / 800);  // about a pixel of the top view
    }
    for (const auto& p : points)
        if (p.allFinite() && cells_.insert(voxelKey(Vec3f(p.x(), p.y(), 0), cell_)).second)
            map_x_.push_back(p.x()), map_y_.push_back(p.y());
}

void RunReport::addFrame(const localization::FrameReport& r, const SE3d& T) {
    ReportFrame f;
    f.t = r.t;
    f.x = T.translation().x(), f.y = T.translation().y();
    f.health = static_cast<int>(r.health);
    f.degenerate = r.degenerate;
    f.prior_used = r.prior_used;
    for (int k = 0; k < 6; ++k) f.prior_w[k] = r.prior_weight[k];
    f.ms = r.ms.total;
    if (r.cov.trace() > 0) {
        f.sigma_xyz = fusion::largestStd(r.cov.topLeftCorner<3, 3>());
        f.sigma_deg = fusion::largestStd(r.cov.bottomRightCorner<3, 3>()) / kDeg;
    }
    frames_.push_back(f);
}

std::string RunReport::html(const io::Json& summary, const std::string& title) const {
    std::vector<double> ts;
    for (const auto& f : frames_) ts.push_back(f.t - frames_.front().t);
    const double half = halfFramePeriod(ts);
    size_t dots = 0, prior_values = 0;
    const SvgPlot top = topView(frames_, map_x_, map_y_, dots);
    const SvgPlot flags = flagsTimeline(frames_, ts, half);
    const SvgPlot prior = priorTimeline(frames_, ts, prior_values);
    const SvgPlot timing = timingTimeline(frames_, ts);
    const SvgPlot sigma = sigmaTimeline(frames_, ts);

    const auto get = [&](const char* a, const char* b = nullptr) -> io::Json {
        if (!summary.contains(a)) return nullptr;
        if (!b) return summary[a];
        return summary[a].contains(b) ? summary[a][b] : io::Json(nullptr);
    };
    const auto text = [](const io::Json& j) {
        return j.is_null() ? std::string("–")
                           : j.is_string() ? j.get<std::string>() : j.is_number() ? number(j.get<double>()) : j.dump();
    };
    const std::string status = text(get("status"));
    std::string h = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
                    xmlEscape("superloc-localize: " + title) + "</title>\n<script>\n" + kErrorScript +
                    "</script>\n<style>" + kStyle + "</style>\n</head>\n<body data-report=\"loading\">\n";
    h += "<h1>superloc-localize run: " + xmlEscape(title) + "</h1>\n<p class=\"status\">Status <span class=\"" +
         std::string(status == "ok" ? "ok" : "failed") + "\">" + xmlEscape(status) + "</span> · method " +
         xmlEscape(text(get("method"))) + " · " + text(get("frames")) + " frames: " +
         text(get("frames_health", "ok")) + " ok, " + text(get("frames_health", "degraded")) + " degraded, " +
         text(get("frames_health", "lost")) + " lost · median " + text(get("ms_per_frame_median")) +
         " ms per frame</p>\n";
    if (const auto e = get("error"); !e.is_null())
        h += "<p class=\"failed\">" + xmlEscape(text(e)) + "</p>\n";
    if (!inputs_.empty()) {
        h += "<table>\n";
        for (const auto& [k, v] : inputs_) h += "<tr><td>" + xmlEscape(k) + "</td><td>" + xmlEscape(v) + "</td></tr>\n";
        h += "</table>\n";
    }
    h += "<pre id=\"errors\"></pre>\n";
    h += figure("top-view", {top},
                "The prior map from above (grey: " + std::to_string(dots) + " dots, about one per pixel, of " +
                    std::to_string(map_x_.size()) +
                    " map cells kept) and the trajectory written (trajectory.tum), coloured by each frame's "
                    "health (frames.csv <code>health</code>; doc/health.md).");
    h += figure("flags", {flags},
                "Top row: each frame's health. Below: the axes flagged degenerate (weak) on the frame "
                "(frames.csv <code>degenerate</code>; doc/localizer.md says what decides it).");
    h += figure("prior", {prior},
                prior_values == 0
                    ? std::string("No frame's solve had an odom_alt prior (frames.csv <code>prior_used</code> "
                                  "is 0 throughout: method icp or ndt, or no odom_alt in the rawlog).")
                    : std::string("log10 of the diagonal information of the odom_alt relative-pose prior in each "
                                  "frame's solve (frames.csv <code>prior_w_x … prior_w_yaw</code>); no line where "
                                  "an axis had no weight or the frame no prior (<code>prior_used</code> 0)."));
    h += figure("sigma", {sigma},
                "The pose's largest std over time, position [m] and rotation [deg], log scale (frames.csv "
                "<code>cov_*</code>, <code>sigma_*</code>); above [health] max_sigma_xyz / max_sigma_deg a "
                "frame is degraded (doc/health.md).");
    h += figure("timing", {timing},
                "Wall time of each frame (frames.csv <code>ms_total</code>), the median dashed. Measured on the "
                "machine of the run, with whatever else ran on it.");
    std::string rows;
    flatten(summary, "", rows);
    h += "<h2>Summary (summary.json)</h2>\n<table>\n" + rows + "</table>\n";
    h += std::string("<script>\n") + kCheckScript + "</script>\n</body>\n</html>\n";
    return h;
}

std::vector<std::string> tilesAlong(const io::MapTileIndex& index,
                                    const std::vector<ReportFrame>& frames, double radius) {
    std::vector<std::string> files;
    const double s = index.tile_size;
    for (const auto& tile : index.tiles) {
        const double x0 = tile.ix * s, y0 = tile.iy * s;
        for (const auto& f : frames) {
            const double dx = std::max({x0 - f.x, 0.0, f.x - (x0 + s)});
            const double dy = std::max({y0 - f.y, 0.0, f.y - (y0 + s)});
            if (std::hypot(dx, dy) <= radius) {
                files.push_back(tile.file);
                break;
            }
        }
    }
    return files;
}

}  // namespace superloc::app
