// A small SVG line-plot writer (no dependencies): axes with ticks, polylines, coloured
// segments, dots, shaded spans, legend. Data coordinates are mapped into a fixed pixel box.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace superloc::app {

class SvgPlot {
 public:
    SvgPlot(double width_px, double height_px, const std::string& title);

    /// Data range shown; with equal_aspect the range is widened so 1 m is as long in x as in y.
    void setRange(double x0, double x1, double y0, double y1, bool equal_aspect = false);
    /// Frame, ticks with values, axis labels and the title; `y_ticks` (value, label), when given,
    /// replace the y axis' numbers (e.g. a row per axis name).
    void axes(const std::string& xlabel, const std::string& ylabel,
              const std::vector<std::pair<double, std::string>>& y_ticks = {});
    void polyline(const std::vector<double>& xs, const std::vector<double>& ys,
                  const std::string& color, double width = 1.5, bool dashed = false);
    void segment(double x0, double y0, double x1, double y1, const std::string& color,
                 double width = 2.0);
    /// Round dots of `radius` px (e.g. a map's points from above), as one path: one dot per
    /// square of 2·radius px (the first point in it; points outside the range are left out), the
    /// square doubled until at most `max_dots` remain, so that the size stays bounded. Returns
    /// the dots drawn.
    size_t dots(const std::vector<double>& xs, const std::vector<double>& ys,
                const std::string& color, double radius, size_t max_dots);
    /// A vertical band over the whole y range between data x0 and x1.
    void spanX(double x0, double x1, const std::string& fill, double opacity = 0.25);
    void hline(double y, const std::string& color, bool dashed = true);
    /// Legend entries (name, colour), drawn in the top-right corner.
    void legend(const std::vector<std::pair<std::string, std::string>>& entries);

    double width() const { return w_; }
    double height() const { return h_; }
    /// The plot's elements, for stacking several plots in one document.
    const std::string& body() const { return body_; }
    /// A complete standalone SVG document.
    std::string str() const;

 private:
    double px(double x) const;
    double py(double y) const;
    double w_, h_;
    double x0_ = 0, x1_ = 1, y0_ = 0, y1_ = 1;
    double left_ = 60, right_ = 15, top_ = 28, bottom_ = 40;  ///< margins [px]
    std::string title_;
    std::string body_;
};

/// Plots stacked top to bottom in one SVG document; `standalone` false leaves out the XML
/// declaration and namespace, for an <svg> element inside an HTML page.
std::string stackSvg(const std::vector<SvgPlot>& plots, bool standalone = true);

/// Colour of a confidence value in [0, 1]: red (0) through yellow to green (1).
std::string gammaColor(double gamma);
/// A distinct colour for the i-th series.
std::string seriesColor(size_t i);
/// Text with XML escapes (&, <, >, ").
std::string xmlEscape(const std::string& s);

}  // namespace superloc::app
