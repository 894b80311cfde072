// Shared by the e2e tests: run LocalizeApp in-process on a rawlog and compare its trajectory
// with a ground truth.
#pragma once

#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/io/tum.h>
#include <superloc/app/localize_app.h>
#include <superloc_testing/testing.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace superloc::testing {

struct LocalizeRun {
    app::RunSummary summary;
    std::vector<localization::FrameReport> frames;  ///< every frame's report, in order
    double ate = 0, worst_m = 0, worst_deg = 0;     ///< against the ground truth
    std::vector<double> err_m, err_deg;             ///< per frame (NaN: no GT)
    std::vector<double> err_z;                      ///< [m] per frame: estimated minus GT height (map z)
    /// Frames more than 0.5 m / 5 deg from the ground truth that were reported `ok`.
    size_t confidentlyWrong() const {
        size_t n = 0;
        for (size_t i = 0; i < frames.size() && i < err_m.size(); ++i)
            n += frames[i].health == localization::Health::Ok && (err_m[i] > 0.5 || err_deg[i] > 5.0);
        return n;
    }
    size_t count(localization::Health h) const {
        size_t n = 0;
        for (const auto& f : frames) n += f.health == h;
        return n;
    }
};

/// `superloc-localize ini/localize.ini ARGS... --out OUT --quiet` in-process, then DIR's
/// trajectory.tum against `gt_tum` (frames interpolated within `max_gap` seconds).
inline LocalizeRun localizeAndCompare(const std::vector<std::string>& args, const std::string& out,
                                      const std::string& gt_tum, double max_gap) {
    std::vector<std::string> all = {sourcePath("ini/localize.ini")};
    all.insert(all.end(), args.begin(), args.end());
    all.insert(all.end(), {"--out", out, "--quiet"});
    LocalizeRun r;
    app::LocalizeApp app;
    EXPECT_EQ(app.initialize(all), app::LocalizeApp::Action::Run);
    EXPECT_EQ(app.run([&r](const localization::FrameReport& f) { r.frames.push_back(f); }), 0);
    r.summary = app.summary();
    const Trajectory gt = io::loadTum(gt_tum);
    const Trajectory est = io::loadTum(out + "/trajectory.tum");
    EXPECT_EQ(est.size(), r.summary.frames);
    double se = 0;
    for (const auto& e : est) {
        const auto g = interpolateAt(gt, e.t, max_gap, 1e-3);
        if (!g) {
            ADD_FAILURE() << "no GT at " << e.t;
            r.err_m.push_back(std::nan("")), r.err_deg.push_back(std::nan("")), r.err_z.push_back(std::nan(""));
            continue;
        }
        const double d = translationDistance(*g, e.pose);
        r.err_m.push_back(d);
        r.err_z.push_back(e.pose.translation().z() - g->translation().z());
        r.err_deg.push_back(rotationAngle(*g, e.pose) * 180 / M_PI);
        se += d * d;
        r.worst_m = std::max(r.worst_m, d);
        r.worst_deg = std::max(r.worst_deg, rotationAngle(*g, e.pose) * 180 / M_PI);
    }
    r.ate = est.empty() ? 0 : std::sqrt(se / static_cast<double>(est.size()));
    return r;
}

}  // namespace superloc::testing
