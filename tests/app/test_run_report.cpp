// report.html's content without a browser (tests/e2e/test_report_browser.cpp renders a real
// run's page in headless Chromium): self-contained, bounded in size for a large map and a long
// run, figures from the frames, the summary's figures, the tiles a run came near.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <superloc/app/run_outputs.h>
#include <superloc/app/run_report.h>
#include <superloc/app/svg_plot.h>
#include <superloc/core/se3.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

using namespace superloc;
using namespace superloc::app;
namespace fs = std::filesystem;

namespace {
size_t count(const std::string& s, const std::string& what) {
    size_t n = 0;
    for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + what.size())) ++n;
    return n;
}

/// A frame at (x, y) with this health, flags and prior.
localization::FrameReport frame(double t, localization::Health health, const std::string& axes,
                                double prior_w_x) {
    localization::FrameReport r;
    r.t = t;
    r.health = health;
    r.degenerate_axes = axes;
    r.degenerate[0] = axes == "x";
    r.prior_used = prior_w_x > 0;
    r.prior_weight[0] = prior_w_x;
    r.ms.total = 10 + t;
    return r;
}

/// Nothing the page would fetch: no URL, no src/href, no stylesheet link or import.
void expectSelfContained(const std::string& html) {
    EXPECT_EQ(html.find("http"), std::string::npos);
    EXPECT_EQ(html.find("src="), std::string::npos);
    EXPECT_EQ(html.find("href="), std::string::npos);
    EXPECT_EQ(html.find("<link"), std::string::npos);
    EXPECT_EQ(html.find("@import"), std::string::npos);
    EXPECT_EQ(html.find("url("), std::string::npos);
}
}  // namespace

TEST(RunReport, FiguresFromTheFramesAndTheSummary) {
    RunReport rep;
    std::vector<Vec3f> map;
    for (int i = 0; i <= 100; ++i) map.emplace_back(0.5f * i, -2.f, 0.f), map.emplace_back(0.5f * i, 2.f, 1.f);
    rep.addMapPoints(map);
    EXPECT_EQ(rep.mapPointsKept(), map.size());  // 6 cm cells (50 m / 800): every point
    rep.addMapPoints(map);                        // the same points again: no new cell
    EXPECT_EQ(rep.mapPointsKept(), map.size());
    // 10 ok frames, 5 degraded with x flagged and an odom_alt prior, 5 lost.
    for (int i = 0; i < 20; ++i) {
        const auto h = i < 10 ? localization::Health::Ok : i < 15 ? localization::Health::Degraded
                                                                  : localization::Health::Lost;
        rep.addFrame(frame(0.1 * i, h, i >= 10 && i < 15 ? "x" : "", i >= 10 && i < 15 ? 1e4 : 0),
                     makePoseRPY(2.0 * i, 0, 0, 0, 0, 0));
    }
    ASSERT_EQ(rep.frames().size(), 20u);
    EXPECT_DOUBLE_EQ(rep.frames()[3].x, 6.0);
    EXPECT_EQ(rep.frames()[12].health, 1);
    EXPECT_TRUE(rep.frames()[12].degenerate[0]);
    rep.setInputs({{"rawlog", "a<b.rawlog"}});
    const io::Json summary = {{"status", "ok"}, {"method", "superloc"}, {"frames", 20},
                              {"frames_health", {{"ok", 10}, {"degraded", 5}, {"lost", 5}}},
                              {"ms_per_frame_median", 10.95}, {"ate_rmse_vs_rawlog_gt", nullptr}};
    const std::string html = rep.html(summary, "run-dir");
    expectSelfContained(html);
    EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
    EXPECT_EQ(count(html, "<figure"), 5u);  // top view, flags, prior, sigma, timing
    EXPECT_EQ(count(html, "<svg "), 5u);
    EXPECT_EQ(html.find("<?xml"), std::string::npos);  // inline SVG, no XML declaration
    EXPECT_NE(html.find("20 frames: 10 ok, 5 degraded, 5 lost"), std::string::npos);
    EXPECT_NE(html.find("a&lt;b.rawlog"), std::string::npos);
    EXPECT_NE(html.find("<td>frames_health.degraded</td><td>5</td>"), std::string::npos);
    EXPECT_NE(html.find("<td>ate_rmse_vs_rawlog_gt</td><td>–</td>"), std::string::npos);
    // One line per stretch of one health state: ok, degraded, lost, each in its colour.
    for (const char* c : {"#2ca02c", "#ff7f0e", "#d62728"})
        EXPECT_NE(html.find("<polyline fill=\"none\" stroke=\"" + std::string(c) + "\""), std::string::npos) << c;
    // The flagged x axis: one bar over the 5 frames, in the x axis' colour.
    EXPECT_EQ(count(html, "stroke=\"" + seriesColor(0) + "\" stroke-width=\"9.00\""), 1u);
    EXPECT_NE(html.find(">pitch</text>"), std::string::npos);  // the rows are named
    // The prior weight 1e4 is drawn at log10 = 4; the caption says what it is.
    EXPECT_NE(html.find("log10 prior_w"), std::string::npos);
    EXPECT_NE(html.find("data-report=\"loading\""), std::string::npos);
    EXPECT_NE(html.find("window.onerror"), std::string::npos);
}

TEST(RunReport, StaysSmallForALargeMapAndALongRun) {
    RunReport rep;
    // A dense 400 m x 400 m map (4 million points) and 36 000 frames (an hour at 10 Hz).
    std::vector<Vec3f> map;
    for (int i = 0; i < 2000; ++i)
        for (int j = 0; j < 2000; ++j) map.emplace_back(0.2f * i, 0.2f * j, 0.f);
    rep.addMapPoints(map);
    EXPECT_LE(rep.mapPointsKept(), 801u * 801u);  // the far edge may start a cell of its own
    for (int i = 0; i < 36000; ++i) {
        auto r = frame(0.1 * i, i % 7 == 0 ? localization::Health::Degraded : localization::Health::Ok,
                       i % 3 == 0 ? "x" : "", i % 2 ? 1e3 + i : 0);
        rep.addFrame(r, makePoseRPY(200 + 150 * std::cos(i * 1e-3), 200 + 150 * std::sin(i * 1e-3), 0, 0, 0, 0));
    }
    // A lost frame reported far away must not shrink the map to a dot.
    rep.addFrame(frame(3600.1, localization::Health::Lost, "", 0), makePoseRPY(1e300, 0, 0, 0, 0, 0));
    const std::string html = rep.html(io::Json{{"status", "ok"}}, "long");
    EXPECT_LT(html.size(), 2u << 20) << "bytes";
    EXPECT_NE(html.find("y [m]"), std::string::npos);
    EXPECT_EQ(html.find("e+300"), std::string::npos);
    // The map's ticks go to 400 m: the range is the map's and the drawable frames'.
    EXPECT_NE(html.find(">400</text>"), std::string::npos);
    expectSelfContained(html);
}

TEST(RunReport, DotsAreBoundedAndThinnedToThePixel) {
    SvgPlot p(200, 200, "dots");
    p.setRange(0, 10, 0, 10);
    std::vector<double> xs, ys;
    for (int i = 0; i <= 1000; ++i) xs.push_back(0.01 * i), ys.push_back(5);  // a line 10 m long
    xs.push_back(50), ys.push_back(50);  // outside the range: left out
    const size_t n = p.dots(xs, ys, "#000", 0.5, 1000);
    // 125 px of plot width, one dot per pixel.
    EXPECT_GE(n, 120u);
    EXPECT_LE(n, 130u);
    EXPECT_EQ(count(p.body(), "h0"), n);
    SvgPlot q(200, 200, "few");
    q.setRange(0, 10, 0, 10);
    EXPECT_LE(q.dots(xs, ys, "#000", 0.5, 20), 20u);
}

TEST(RunReport, TilesAlongTheFrames) {
    io::MapTileIndex index;
    index.tile_size = 10;
    for (int ix = -2; ix <= 2; ++ix) index.tiles.push_back({ix, 0, 1, "t" + std::to_string(ix)});
    std::vector<ReportFrame> frames(2);
    frames[0].x = 1, frames[0].y = 5;   // in tile 0
    frames[1].x = 12, frames[1].y = 5;  // in tile 1
    // Within 4 m: tiles 0 and 1 (and tile -1, 1 m away from the first frame).
    EXPECT_EQ(tilesAlong(index, frames, 4), (std::vector<std::string>{"t-1", "t0", "t1"}));
    EXPECT_EQ(tilesAlong(index, frames, 0.5), (std::vector<std::string>{"t0", "t1"}));
    EXPECT_TRUE(tilesAlong(index, {}, 100).empty());
}

// RunOutputs writes report.html at the end with the other outputs, only when asked for.
TEST(RunReport, WrittenByRunOutputsWhenAsked) {
    const std::string d = superloc::testing::freshDir("run_report_outputs");
    for (bool with : {true, false}) {
        const std::string dir = d + (with ? "/with" : "/without");
        {
            RunOutputs out(dir, 0.1, with);
            ASSERT_EQ(out.report() != nullptr, with);
            if (out.report()) out.report()->addMapPoints({Vec3f(0, 0, 0), Vec3f(5, 5, 0)});
            for (int i = 0; i < 3; ++i)
                out.addFrame(frame(i, localization::Health::Ok, "", 0), makePoseRPY(i, 1, 0, 0, 0, 0), {});
            EXPECT_FALSE(fs::exists(dir + "/report.html"));  // at the end only
            RunSummary s;
            s.method = "icp", s.frames = 3, s.health = {3, 0, 0};
            out.finish(s);
        }
        EXPECT_TRUE(fs::exists(dir + "/summary.json"));
        EXPECT_EQ(fs::exists(dir + "/report.html"), with);
        if (!with) continue;
        std::ifstream in(dir + "/report.html");
        std::stringstream ss;
        ss << in.rdbuf();
        EXPECT_NE(ss.str().find("3 frames: 3 ok, 0 degraded, 0 lost"), std::string::npos);
        EXPECT_NE(ss.str().find("No frame's solve had an odom_alt prior"), std::string::npos);
    }
}
