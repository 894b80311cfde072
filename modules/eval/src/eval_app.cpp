#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <superloc/core/config.h>
#include <superloc/core/cli.h>
#include <superloc/eval/eval_app.h>
#include <superloc/eval/evaluation.h>
#include <superloc/eval/report_plots.h>
#include <superloc/io/json_file.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace superloc::eval {

std::string EvalApp::usage() {
    return "Usage: superloc-eval --est TUM --gt TUM [options]\n"
           "Evaluates an estimated trajectory (and map) against ground truth (DESIGN §8).\n"
           "  --est TUM          estimated trajectory (TUM: t x y z qx qy qz qw)\n"
           "  --gt TUM           ground-truth trajectory\n"
           "  --est-map F        localized map (.pcd/.ply/...), with --gt-map: map outlier %\n"
           "  --gt-map F         ground-truth map\n"
           "  --frames CSV       the localizer's frames.csv: timing, gamma plot\n"
           "  --json OUT         write all metrics (and F1 curves) as JSON\n"
           "  --plots DIR        write trajectory.svg, f1_trans.svg, f1_rot.svg (+ gamma.svg)\n"
           "  --align            SE(3) Umeyama alignment before ATE (default: none, map frame)\n"
           "  --config INI       read section [eval] of an INI file\n"
           "  --set eval.KEY=V   override one [eval] key (repeatable)\n"
           "  --dump-config      print the effective [eval] section and exit\n"
           "  --help             this text\n";
}

void EvalApp::initialize(const std::vector<std::string>& args) {
    mrpt::config::CConfigFileMemory cfg;
    std::string source = "command line";
    std::vector<std::string> sets;
    bool align_flag = false;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const auto next = [&] { return flagValue(args, i); };
        if (a == "--help" || a == "-h")
            help = true;
        else if (a == "--est")
            est_path = next();
        else if (a == "--gt")
            gt_path = next();
        else if (a == "--est-map")
            est_map_path = next();
        else if (a == "--gt-map")
            gt_map_path = next();
        else if (a == "--frames")
            frames_path = next();
        else if (a == "--json")
            json_path = next();
        else if (a == "--plots")
            plots_dir = next();
        else if (a == "--align")
            align_flag = true;
        else if (a == "--dump-config")
            dump_config = true;
        else if (a == "--set")
            sets.push_back(next());
        else if (a == "--config") {
            source = next();
            if (!std::filesystem::is_regular_file(source))
                throw std::invalid_argument("--config " + source + ": no such file");
            std::ifstream in(source);
            std::stringstream text;
            text << in.rdbuf();
            setIniContent(cfg, text.str(), source);
        } else
            throw std::invalid_argument("unknown argument '" + a + "' (see --help)");
    }
    for (const auto& s : sets) applyOverride(cfg, s);
    params = loadParams<EvalParams>(cfg, "eval", sets.empty() ? source : source + " / --set");
    if (align_flag) params.align = true;
    if (help || dump_config) return;
    if (est_path.empty()) throw std::invalid_argument("--est TUM is required (see --help)");
    if (gt_path.empty()) throw std::invalid_argument("--gt TUM is required (see --help)");
    if (est_map_path.empty() != gt_map_path.empty())
        throw std::invalid_argument("--est-map and --gt-map go together");
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
    PointCloud est_map, gt_map;
    if (!est_map_path.empty()) {
        est_map = io::loadPointCloud(est_map_path);
        gt_map = io::loadPointCloud(gt_map_path);
        if (gt_map.empty()) throw std::runtime_error(gt_map_path + ": no points");
        if (est_map.empty()) throw std::runtime_error(est_map_path + ": no points");
    }
    FrameLog frames;
    if (!frames_path.empty()) frames = loadFrameLog(frames_path);
    const bool maps = !est_map_path.empty();
    const EvalResult r =
        evaluate(est, gt, params, maps ? &est_map : nullptr, maps ? &gt_map : nullptr,
                 frames_path.empty() ? nullptr : &frames);
    out << summaryMarkdown(r);
    if (!json_path.empty()) io::saveJson(json_path, toJson(r));
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
    }
    return 0;
}

}  // namespace superloc::eval
