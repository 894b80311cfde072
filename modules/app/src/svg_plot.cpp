#include <superloc/app/svg_plot.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <unordered_set>

namespace superloc::app {
namespace {

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return buf;
}

std::string tickLabel(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", std::abs(v) < 1e-12 ? 0.0 : v);
    return buf;
}

/// A "nice" tick step (1, 2 or 5 times a power of ten) giving about 5 ticks over `range`.
double tickStep(double range) {
    if (!(range > 0)) return 1;
    const double raw = range / 5;
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

}  // namespace

std::string xmlEscape(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '&')
            o += "&amp;";
        else if (c == '<')
            o += "&lt;";
        else if (c == '>')
            o += "&gt;";
        else if (c == '"')
            o += "&quot;";
        else
            o += c;
    }
    return o;
}

SvgPlot::SvgPlot(double width_px, double height_px, const std::string& title)
    : w_(width_px), h_(height_px), title_(title) {}

void SvgPlot::setRange(double x0, double x1, double y0, double y1, bool equal_aspect) {
    if (!(x1 > x0)) x0 -= 0.5, x1 = x0 + 1;
    if (!(y1 > y0)) y0 -= 0.5, y1 = y0 + 1;
    if (equal_aspect) {
        const double sx = (x1 - x0) / (w_ - left_ - right_), sy = (y1 - y0) / (h_ - top_ - bottom_);
        const double s = std::max(sx, sy);
        const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
        x0 = cx - 0.5 * s * (w_ - left_ - right_), x1 = cx + 0.5 * s * (w_ - left_ - right_);
        y0 = cy - 0.5 * s * (h_ - top_ - bottom_), y1 = cy + 0.5 * s * (h_ - top_ - bottom_);
    }
    x0_ = x0, x1_ = x1, y0_ = y0, y1_ = y1;
}

double SvgPlot::px(double x) const {
    return left_ + (x - x0_) / (x1_ - x0_) * (w_ - left_ - right_);
}
double SvgPlot::py(double y) const {
    return h_ - bottom_ - (y - y0_) / (y1_ - y0_) * (h_ - top_ - bottom_);
}

void SvgPlot::axes(const std::string& xlabel, const std::string& ylabel,
                   const std::vector<std::pair<double, std::string>>& y_ticks) {
    std::string& b = body_;
    b += "<rect x=\"" + num(left_) + "\" y=\"" + num(top_) + "\" width=\"" +
         num(w_ - left_ - right_) + "\" height=\"" + num(h_ - top_ - bottom_) +
         "\" fill=\"none\" stroke=\"#333\"/>\n";
    const double sx = tickStep(x1_ - x0_), sy = tickStep(y1_ - y0_);
    for (double x = std::ceil(x0_ / sx) * sx; x <= x1_ + 1e-9 * sx; x += sx)
        b += "<line x1=\"" + num(px(x)) + "\" y1=\"" + num(h_ - bottom_) + "\" x2=\"" + num(px(x)) +
             "\" y2=\"" + num(h_ - bottom_ + 4) + "\" stroke=\"#333\"/><text x=\"" + num(px(x)) +
             "\" y=\"" + num(h_ - bottom_ + 15) + "\" font-size=\"10\" text-anchor=\"middle\">" +
             tickLabel(x) + "</text>\n";
    std::vector<std::pair<double, std::string>> yt = y_ticks;
    if (yt.empty())
        for (double y = std::ceil(y0_ / sy) * sy; y <= y1_ + 1e-9 * sy; y += sy)
            yt.emplace_back(y, tickLabel(y));
    for (const auto& [y, label] : yt)
        b += "<line x1=\"" + num(left_ - 4) + "\" y1=\"" + num(py(y)) + "\" x2=\"" + num(left_) +
             "\" y2=\"" + num(py(y)) + "\" stroke=\"#333\"/><text x=\"" + num(left_ - 6) +
             "\" y=\"" + num(py(y) + 3) + "\" font-size=\"10\" text-anchor=\"end\">" +
             xmlEscape(label) + "</text>\n";
    b += "<text x=\"" + num(0.5 * (left_ + w_ - right_)) + "\" y=\"" + num(h_ - 6) +
         "\" font-size=\"11\" text-anchor=\"middle\">" + xmlEscape(xlabel) + "</text>\n";
    b += "<text x=\"12\" y=\"" + num(0.5 * (top_ + h_ - bottom_)) +
         "\" font-size=\"11\" text-anchor=\"middle\" transform=\"rotate(-90 12 " +
         num(0.5 * (top_ + h_ - bottom_)) + ")\">" + xmlEscape(ylabel) + "</text>\n";
    b += "<text x=\"" + num(left_) + "\" y=\"18\" font-size=\"13\" font-weight=\"bold\">" +
         xmlEscape(title_) + "</text>\n";
}

void SvgPlot::polyline(const std::vector<double>& xs, const std::vector<double>& ys,
                       const std::string& color, double width, bool dashed) {
    // NaN values break the line into separate runs.
    std::string pts;
    auto flush = [&] {
        if (!pts.empty())
            body_ += "<polyline fill=\"none\" stroke=\"" + color + "\" stroke-width=\"" +
                     num(width) + "\"" + (dashed ? " stroke-dasharray=\"5,3\"" : "") +
                     " points=\"" + pts + "\"/>\n";
        pts.clear();
    };
    for (size_t i = 0; i < std::min(xs.size(), ys.size()); ++i) {
        if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) {
            flush();
            continue;
        }
        pts += num(px(xs[i])) + "," + num(py(ys[i])) + " ";
    }
    flush();
}

void SvgPlot::segment(double x0, double y0, double x1, double y1, const std::string& color,
                      double width) {
    body_ += "<line x1=\"" + num(px(x0)) + "\" y1=\"" + num(py(y0)) + "\" x2=\"" + num(px(x1)) +
             "\" y2=\"" + num(py(y1)) + "\" stroke=\"" + color + "\" stroke-width=\"" + num(width) +
             "\" stroke-linecap=\"round\"/>\n";
}

size_t SvgPlot::dots(const std::vector<double>& xs, const std::vector<double>& ys,
                     const std::string& color, double radius, size_t max_dots) {
    // Pixel positions inside the frame, then one per cell of `cell` px.
    std::vector<std::pair<double, double>> in;
    for (size_t i = 0; i < std::min(xs.size(), ys.size()); ++i) {
        const double u = px(xs[i]), v = py(ys[i]);
        if (std::isfinite(u) && std::isfinite(v) && u >= left_ && u <= w_ - right_ && v >= top_ &&
            v <= h_ - bottom_)
            in.emplace_back(u, v);
    }
    std::vector<std::pair<double, double>> kept;
    for (double cell = std::max(2 * radius, 0.5);; cell *= 2) {
        std::unordered_set<int64_t> seen;
        kept.clear();
        for (const auto& [u, v] : in) {
            const int64_t key = static_cast<int64_t>(u / cell) * 1000003 + static_cast<int64_t>(v / cell);
            if (seen.insert(key).second) kept.emplace_back(u, v);
        }
        if (kept.size() <= std::max<size_t>(max_dots, 1)) break;
    }
    if (kept.empty()) return 0;
    // A zero-length line with round caps is a dot of the stroke's width.
    std::string d;
    char buf[48];
    for (const auto& [u, v] : kept) {
        std::snprintf(buf, sizeof buf, "M%.1f %.1fh0", u, v);
        d += buf;
    }
    body_ += "<path fill=\"none\" stroke=\"" + color + "\" stroke-width=\"" + num(2 * radius) +
             "\" stroke-linecap=\"round\" d=\"" + d + "\"/>\n";
    return kept.size();
}

void SvgPlot::spanX(double x0, double x1, const std::string& fill, double opacity) {
    const double a = std::max(px(x0), left_), b = std::min(px(x1), w_ - right_);
    if (b <= a) return;
    body_ += "<rect x=\"" + num(a) + "\" y=\"" + num(top_) + "\" width=\"" + num(b - a) +
             "\" height=\"" + num(h_ - top_ - bottom_) + "\" fill=\"" + fill +
             "\" fill-opacity=\"" + num(opacity) + "\"/>\n";
}

void SvgPlot::hline(double y, const std::string& color, bool dashed) {
    body_ += "<line x1=\"" + num(left_) + "\" y1=\"" + num(py(y)) + "\" x2=\"" + num(w_ - right_) +
             "\" y2=\"" + num(py(y)) + "\" stroke=\"" + color + "\"" +
             (dashed ? " stroke-dasharray=\"4,3\"" : "") + "/>\n";
}

void SvgPlot::legend(const std::vector<std::pair<std::string, std::string>>& entries) {
    double y = top_ + 14;
    const double x = w_ - right_ - 130;
    if (!entries.empty())  // a light backing, so that the entries stay legible over the data
        body_ += "<rect x=\"" + num(x - 4) + "\" y=\"" + num(top_ + 3) + "\" width=\"128\" height=\"" +
                 num(14.0 * static_cast<double>(entries.size()) + 4) +
                 "\" fill=\"white\" fill-opacity=\"0.85\"/>\n";
    for (const auto& [name, color] : entries) {
        body_ += "<line x1=\"" + num(x) + "\" y1=\"" + num(y - 4) + "\" x2=\"" + num(x + 18) +
                 "\" y2=\"" + num(y - 4) + "\" stroke=\"" + color +
                 "\" stroke-width=\"3\"/><text x=\"" + num(x + 22) + "\" y=\"" + num(y) +
                 "\" font-size=\"10\">" + xmlEscape(name) + "</text>\n";
        y += 14;
    }
}

std::string SvgPlot::str() const { return stackSvg({*this}); }

std::string stackSvg(const std::vector<SvgPlot>& plots, bool standalone) {
    double w = 0, h = 0;
    for (const auto& p : plots) w = std::max(w, p.width()), h += p.height();
    std::string s = standalone ? "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg "
                                 "xmlns=\"http://www.w3.org/2000/svg\" "
                               : "<svg ";
    s += "width=\"" + num(w) + "\" height=\"" + num(h) + "\" viewBox=\"0 0 " + num(w) + " " +
         num(h) +
         "\" font-family=\"sans-serif\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    double y = 0;
    for (const auto& p : plots) {
        s += "<g transform=\"translate(0," + num(y) + ")\">\n" + p.body() + "</g>\n";
        y += p.height();
    }
    return s + "</svg>\n";
}

std::string gammaColor(double gamma) {
    const double g = std::clamp(std::isfinite(gamma) ? gamma : 0.0, 0.0, 1.0);
    return "hsl(" + std::to_string(static_cast<int>(std::lround(120 * g))) + ",85%,42%)";
}

std::string seriesColor(size_t i) {
    static const char* kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                     "#9467bd", "#8c564b", "#e377c2", "#17becf"};
    return kPalette[i % (sizeof kPalette / sizeof *kPalette)];
}

}  // namespace superloc::app
