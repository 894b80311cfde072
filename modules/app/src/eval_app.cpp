#include <CLI/CLI.hpp>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <superloc/core/config.h>
#include <superloc/app/command_line.h>
#include <superloc/app/eval_app.h>
#include <superloc/app/ini_sections.h>
#include <superloc/eval/evaluation.h>
#include <superloc/app/report_plots.h>
#include <superloc/io/json_file.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace superloc::app {

namespace {

struct EvalFlags {
    std::string config;
    std::vector<std::string> sets;
    bool align = false;
};

void defineCommandLine(CLI::App& cli, EvalApp& app, EvalFlags& f) {
    cli.description("Evaluates an estimated trajectory (and map) against ground truth (doc/evaluation.md).");
    cli.add_option("--est", app.est_path, "estimated trajectory (TUM: t x y z qx qy qz qw)")->type_name("TUM");
    cli.add_option("--gt", app.gt_path, "ground-truth trajectory")->type_name("TUM");
    cli.add_option("--est-map", app.est_map_path, "localized map (.pcd/.ply/...), with --gt-map: map outlier %");
    cli.add_option("--gt-map", app.gt_map_path, "ground-truth map")->needs("--est-map");
    cli.get_option("--est-map")->needs("--gt-map");
    cli.add_option("--frames", app.frames_path, "the localizer's frames.csv: timing, gamma plot, health against the error, the covariance's NEES\n(and trajectory_cov.txt beside it: the full 6 x 6)")->type_name("CSV");
    cli.add_option("--json", app.json_path, "write all metrics (and F1 curves) as JSON");
    cli.add_option("--plots", app.plots_dir, "write trajectory.svg, f1_trans.svg, f1_rot.svg (+ gamma.svg)")
        ->type_name("DIR");
    cli.add_flag("--align", f.align, "SE(3) Umeyama alignment before ATE (default: none, map frame)");
    cli.add_option("--config", f.config, "read section [eval] of an INI file")->type_name("INI");
    addSetOption(cli, f.sets);
    cli.add_flag("--dump-config", app.dump_config, "print the effective [eval] section and exit");
}

}  // namespace

std::string EvalApp::usage() {
    CLI::App cli("", "superloc-eval");
    EvalApp app;
    EvalFlags f;
    defineCommandLine(cli, app, f);
    return helpText(cli);
}

void EvalApp::initialize(const std::vector<std::string>& args) {
    CLI::App cli("", "superloc-eval");
    EvalFlags f;
    defineCommandLine(cli, *this, f);
    if (!parseCommandLine(cli, args)) {
        help = true;
        return;
    }
    mrpt::config::CConfigFileMemory cfg;
    std::string source = "command line";
    if (!f.config.empty()) {
        source = f.config;
        loadIniFile(cfg, source);
    }
    for (const auto& s : f.sets) applyOverride(cfg, s);
    checkSections(cfg, evalSections(), f.config, f.sets);
    params = loadParams<eval::EvalParams>(cfg, "eval", f.sets.empty() ? source : source + " / --set");
    if (f.align) params.align = true;
    if (dump_config) return;
    if (est_path.empty()) throw std::invalid_argument("--est TUM is required (see --help)");
    if (gt_path.empty()) throw std::invalid_argument("--gt TUM is required (see --help)");
}

int EvalApp::run(std::ostream& out) {
    if (help) {
        out << usage();
        return 0;
    }
    if (dump_config) {
        mrpt::config::CConfigFileMemory c;
        params.saveToConfigFile(c, "eval");
        out << c.getContent();
        return 0;
    }
    const Trajectory est = io::loadTum(est_path);
    const Trajectory gt = io::loadTum(gt_path);
    if (gt.empty()) throw std::runtime_error(gt_path + ": no poses");
    if (est.empty()) throw std::runtime_error(est_path + ": no poses");
    PointCloud est_map, gt_map;
    if (!est_map_path.empty()) {
        est_map = io::loadPointCloud(est_map_path);
        gt_map = io::loadPointCloud(gt_map_path);
        if (gt_map.empty()) throw std::runtime_error(gt_map_path + ": no points");
        if (est_map.empty()) throw std::runtime_error(est_map_path + ": no points");
    }
    eval::FrameLog frames;
    if (!frames_path.empty()) frames = eval::loadFrameLog(frames_path);
    const bool maps = !est_map_path.empty();
    const eval::EvalResult r =
        eval::evaluate(est, gt, params, maps ? &est_map : nullptr, maps ? &gt_map : nullptr,
                 frames_path.empty() ? nullptr : &frames);
    // Nothing matched: every error statistic would be 0, a perfect score for no comparison.
    if (r.matched_frames == 0) {
        char span[200];
        std::snprintf(span, sizeof span,
                      " within [eval] assoc_tolerance = %g s (the estimate spans %.3f..%.3f s, the ground truth "
                      "%.3f..%.3f s)",
                      params.assoc_tolerance, est.front().t, est.back().t, gt.front().t, gt.back().t);
        throw std::runtime_error("no pose of " + est_path + " has a ground-truth pose of " + gt_path + span);
    }
    out << eval::summaryMarkdown(r);
    if (!json_path.empty()) io::saveJson(json_path, eval::toJson(r));
    if (!plots_dir.empty()) {
        std::filesystem::create_directories(plots_dir);
        const auto p = [&](const std::string& f) {
            return (std::filesystem::path(plots_dir) / f).string();
        };
        std::vector<double> g;
        if (frames.has_gamma) g = minTranslationGamma(est, frames, params.assoc_tolerance);
        writeTextFile(p("trajectory.svg"), trajectoryTopViewSvg(gt, est, g, "Top view"));
        writeTextFile(p("f1_trans.svg"),
                      f1CurvesSvg({{"estimate", r.rp}}, false, "Robustness F1 (translation)"));
        writeTextFile(p("f1_rot.svg"),
                      f1CurvesSvg({{"estimate", r.rr}}, true, "Robustness F1 (rotation)"));
        if (frames.has_gamma)
            writeTextFile(p("gamma.svg"), gammaTimelineSvg(frames, 0.2, "Confidence γ per axis"));
        if (r.consistency) writeTextFile(p("nees.svg"), neesTimelineSvg(*r.consistency, "Covariance consistency"));
    }
    return 0;
}

}  // namespace superloc::app
