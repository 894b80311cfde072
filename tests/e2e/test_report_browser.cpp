// report.html of a real run (the bundled office fixture, rawlogs/README.md) opened by a real
// browser: Debian's headless Chromium (scripts/install-deps.sh installs it; the test skips
// without it). The page's script marks <body data-report="drawn N"> once every figure has a
// drawing, or "error" with the message in <pre id="errors"> on a script error: the test reads
// both from the DOM the browser dumps, takes a screenshot, and checks that a script error on the
// page does show (so that the first check can fail).
#include <gtest/gtest.h>
#include <superloc/app/localize_app.h>
#include <superloc/app/process.h>
#include <superloc_testing/testing.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace superloc;
using namespace superloc::app;
namespace fs = std::filesystem;

namespace {
std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string findBrowser() {
    for (const char* name : {"chromium", "chromium-browser"})
        if (auto t = findTool(name, "/nonexistent"); !t.empty()) return t;
    return "";
}

/// Runs the browser headless on `page` with `extra` flags; its output (and the dumped DOM) is
/// in `log`. Flags for a root user in CI: no sandbox, no GPU, no network of its own, a fresh
/// profile each time.
ProcessResult browse(const std::string& browser, const std::string& dir, const std::string& page,
                     const std::vector<std::string>& extra, const std::string& log) {
    static int profile = 0;
    const std::string user_dir = dir + "/profile-" + std::to_string(profile++);
    fs::create_directories(user_dir);
    std::vector<std::string> argv = {browser, "--headless", "--no-sandbox", "--disable-gpu",
                                     "--disable-quic", "--no-first-run", "--disable-background-networking",
                                     "--disable-component-update", "--disable-sync",
                                     "--user-data-dir=" + user_dir};
    argv.insert(argv.end(), extra.begin(), extra.end());
    argv.push_back("file://" + fs::absolute(page).string());
    return runProcess(argv, log, 60);
}
}  // namespace

TEST(ReportBrowser, ARunsReportRendersWithoutErrors) {
    const std::string browser = findBrowser();
    if (browser.empty()) GTEST_SKIP() << "chromium not found on PATH (scripts/install-deps.sh installs it)";
    const std::string d = superloc::testing::freshDir("report_browser");
    const std::string fixtures = superloc::testing::sourcePath("rawlogs");
    LocalizeApp app;
    ASSERT_EQ(app.initialize(std::vector<std::string>{
                  superloc::testing::sourcePath("ini/localize.ini"), "--rawlog", fixtures + "/office-tiny.rawlog",
                  "--map", fixtures + "/office-tiny-map.pcd", "--initial-pose-tum", fixtures + "/office-tiny-gt.tum",
                  "--method", "superloc", "--out", d + "/run", "--quiet"}),
              LocalizeApp::Action::Run);
    ASSERT_EQ(app.run(), 0);
    const std::string page = d + "/run/report.html";
    ASSERT_TRUE(fs::exists(page));
    EXPECT_LT(fs::file_size(page), 2u << 20);

    // The DOM after the page's scripts ran: every figure drawn, no script error.
    ASSERT_TRUE(browse(browser, d, page, {"--dump-dom"}, d + "/dom.txt").ok()) << slurp(d + "/dom.txt");
    const std::string dom = slurp(d + "/dom.txt");
    EXPECT_NE(dom.find("<body data-report=\"drawn 5\">"), std::string::npos) << dom.substr(0, 3000);
    EXPECT_NE(dom.find("<pre id=\"errors\"></pre>"), std::string::npos);
    EXPECT_EQ(dom.find("data-script-error=\""), std::string::npos);
    EXPECT_NE(dom.find("10 frames: 10 ok, 0 degraded, 0 lost"), std::string::npos);

    // A screenshot: a PNG of the window's size with the figures on it (a blank page is ~5 KB).
    ASSERT_TRUE(browse(browser, d, page, {"--window-size=900,1600", "--screenshot=" + d + "/shot.png"},
                       d + "/shot.txt")
                    .ok())
        << slurp(d + "/shot.txt");
    const std::string png = slurp(d + "/shot.png");
    ASSERT_GT(png.size(), 24u);
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    const auto be32 = [&](size_t at) {
        return (uint32_t(uint8_t(png[at])) << 24) | (uint32_t(uint8_t(png[at + 1])) << 16) |
               (uint32_t(uint8_t(png[at + 2])) << 8) | uint32_t(uint8_t(png[at + 3]));
    };
    EXPECT_EQ(be32(16), 900u);  // IHDR width, height
    EXPECT_EQ(be32(20), 1600u);
    EXPECT_GT(png.size(), 30000u) << "bytes: an empty page?";

    // The same page with a failing script: the error shows on the page and marks it.
    std::string html = slurp(page);
    html.insert(html.rfind("</body>"), "<script>noSuchFunction();</script>\n");
    const std::string broken = d + "/broken.html";
    std::ofstream(broken) << html;
    ASSERT_TRUE(browse(browser, d, broken, {"--dump-dom"}, d + "/dom-broken.txt").ok());
    const std::string dom_broken = slurp(d + "/dom-broken.txt");
    EXPECT_NE(dom_broken.find("<body data-report=\"error\">"), std::string::npos) << dom_broken.substr(0, 3000);
    EXPECT_NE(dom_broken.find("noSuchFunction is not defined"), std::string::npos);
}

// [run] save_report = false: no report.html, the other outputs as ever (no browser needed).
TEST(ReportBrowser, SwitchedOffByRunSaveReport) {
    const std::string d = superloc::testing::freshDir("report_off");
    const std::string fixtures = superloc::testing::sourcePath("rawlogs");
    for (const char* value : {"false", "true"}) {
        const std::string out = d + "/run-" + value;
        LocalizeApp app;
        ASSERT_EQ(app.initialize(std::vector<std::string>{
                      superloc::testing::sourcePath("ini/localize.ini"), "--rawlog", fixtures + "/office-tiny.rawlog",
                      "--map", fixtures + "/office-tiny-map.pcd", "--initial-pose-tum",
                      fixtures + "/office-tiny-gt.tum", "--out", out, "--quiet", "--set",
                      std::string("run.save_report=") + value}),
                  LocalizeApp::Action::Run);
        ASSERT_EQ(app.run(), 0);
        for (const char* f : {"trajectory.tum", "frames.csv", "summary.json", "localized_map.pcd"})
            EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
        EXPECT_EQ(fs::exists(out + "/report.html"), std::string(value) == "true");
    }
    LocalizeApp dump;
    ASSERT_EQ(dump.initialize(std::vector<std::string>{superloc::testing::sourcePath("ini/localize.ini"),
                                                       "--dump-config"}),
              LocalizeApp::Action::DumpConfig);
    EXPECT_NE(dump.dumpConfig().find("save_report"), std::string::npos);
}

// [run] save_observability_scan = false: no observability_scan.ply, the trajectory the same.
TEST(ReportBrowser, ObservabilityScanSwitchedOffByRun) {
    const std::string d = superloc::testing::freshDir("obs_scan_off");
    const std::string fixtures = superloc::testing::sourcePath("rawlogs");
    std::string trajectory[2];
    for (const bool on : {false, true}) {
        const std::string out = d + (on ? "/on" : "/off");
        LocalizeApp app;
        ASSERT_EQ(app.initialize(std::vector<std::string>{
                      superloc::testing::sourcePath("ini/localize.ini"), "--rawlog", fixtures + "/office-tiny.rawlog",
                      "--map", fixtures + "/office-tiny-map.pcd", "--initial-pose-tum",
                      fixtures + "/office-tiny-gt.tum", "--out", out, "--quiet", "--set",
                      std::string("run.save_observability_scan=") + (on ? "true" : "false")}),
                  LocalizeApp::Action::Run);
        ASSERT_EQ(app.run(), 0);
        EXPECT_EQ(fs::exists(out + "/observability_scan.ply"), on);
        for (const char* f : {"trajectory.tum", "frames.csv", "summary.json", "localized_map.pcd"})
            EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
        trajectory[on] = slurp(out + "/trajectory.tum");
    }
    EXPECT_FALSE(trajectory[0].empty());
    EXPECT_EQ(trajectory[0], trajectory[1]);
}
