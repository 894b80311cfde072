#include <CLI/CLI.hpp>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/app/bench_app.h>
#include <superloc/app/command_line.h>
#include <superloc/app/ini_sections.h>
#include <superloc/app/process.h>
#include <superloc/app/report_plots.h>
#include <superloc/app/task_queue.h>
#include <superloc/core/config.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace superloc::app {
namespace fs = std::filesystem;
namespace {

std::string status(const ProcessResult& p, double timeout_s) {
    if (!p.started) return "could not start";
    if (p.timed_out) return "timeout after " + std::to_string(static_cast<int>(timeout_s)) + " s";
    if (p.exit_code != 0) return "exit " + std::to_string(p.exit_code);
    return "ok";
}

bool allExist(const std::vector<std::string>& paths) {
    for (const auto& p : paths)
        if (!fs::exists(p)) return false;
    return true;
}

/// --jobs: a whole number from 1 to kMaxChildren ("0", "-1", "2.5", "two" are not).
unsigned parseJobs(const std::string& s) {
    const bool digits = !s.empty() && s.size() <= 9 &&
                        std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
    const unsigned long n = digits ? std::stoul(s) : 0;
    if (n < 1 || n > kMaxChildren)
        throw std::invalid_argument("--jobs: '" + s + "' is not a whole number from 1 to " +
                                    std::to_string(kMaxChildren));
    return static_cast<unsigned>(n);
}

/// The progress line of a finished run: status, then ATE, Rp, Rr and the map outliers.
std::string outcome(const RunRecord& r) {
    std::string line = r.status;
    if (r.result) {
        char buf[160];
        std::snprintf(buf, sizeof buf, ", ATE %.3f m, Rp %.3f, Rr %.3f", r.result->ate.trans.rmse,
                      r.result->rp.area, r.result->rr.area);
        line += buf;
        if (r.result->map) {
            std::snprintf(buf, sizeof buf, ", map outliers %.2f %%", r.result->map->outlier_percent);
            line += buf;
        }
    }
    return line;
}

struct BenchFlags {
    std::string suite_path, only_seq, only_meth, jobs;
    std::vector<std::string> localize_sets;
};

void defineCommandLine(CLI::App& cli, BenchApp& app, BenchFlags& f) {
    cli.description(
        "Runs every method of a suite on every sequence, evaluates, writes DIR/results.md,\n"
        "DIR/results.json and DIR/*.svg (doc/evaluation.md).");
    cli.add_option("SUITE.ini", f.suite_path, "the suite (e.g. ini/bench/quick.ini)")->required();
    cli.add_option("--out", app.out_dir, "output folder (data/, runs/, logs/ and the results)")
        ->type_name("DIR")
        ->required();
    cli.add_option("--data", app.data_dir, "real data sets folder (default: the build's SUPERLOC_SHARED_DATA)")
        ->type_name("DIR");
    cli.add_option("--tools", app.tools_dir,
                   "folder of superloc-sim/-import/-map/-localize (default: next to this executable,\n"
                   "the build tree, then PATH)")
        ->type_name("DIR");
    cli.add_option("--sequences", f.only_seq, "run only these sequences of the suite")->type_name("\"a b\"");
    cli.add_option("--methods", f.only_meth, "run only these methods of the suite")->type_name("\"m1 m2\"");
    cli.add_flag("--fresh", app.fresh, "regenerate simulated/imported data even if present");
    cli.add_flag("--drop-data", app.drop_data,
                 "delete a sequence's rawlog and maps once all its runs are evaluated (a big suite's\n"
                 "simulated data take ~1.4 GB per 150 s sequence; its GT trajectory stays)");
    cli.add_option("--localize-set", f.localize_sets,
                   "one more --set for every superloc-localize run (after the suite's [suite] keys), e.g.\n"
                   "--localize-set localization.association=voxel (repeatable)")
        ->type_name("SECTION.KEY=VALUE");
    cli.add_option("--jobs", f.jobs,
                   "children run at once (default: the number of cores): a sequence's preparation,\n"
                   "or one localize run and its evaluation; the results are those of --jobs 1, but\n"
                   "the runs share the cores, so their times (ms per frame, wall) are higher")
        ->type_name("N");
}

}  // namespace

std::string BenchApp::usage() {
    CLI::App cli("", "superloc-bench");
    BenchApp app;
    BenchFlags f;
    defineCommandLine(cli, app, f);
    return helpText(cli);
}

void BenchApp::initialize(const std::vector<std::string>& args) {
    CLI::App cli("", "superloc-bench");
    BenchFlags f;
    defineCommandLine(cli, *this, f);
    if (!parseCommandLine(cli, args)) {
        help = true;
        return;
    }
    const std::string& suite_path = f.suite_path;
    const bool seq_given = cli.count("--sequences") > 0, meth_given = cli.count("--methods") > 0;
    const std::string &only_seq = f.only_seq, &only_meth = f.only_meth;
    if (tools_dir.empty()) tools_dir = selfDir();
    suite = loadSuite(suite_path, data_dir);
    if (seq_given) {
        std::vector<SequenceSpec> keep;
        for (const auto& name : splitWords(only_seq)) {
            bool found = false;
            for (const auto& s : suite.sequences)
                if (s.name == name) keep.push_back(s), found = true;
            if (!found)
                throw std::invalid_argument("--sequences: '" + name + "' is not in " + suite_path);
        }
        suite.sequences = keep;
    }
    if (meth_given) suite.methods = splitWords(only_meth);
    if (suite.methods.empty()) throw std::invalid_argument("--methods: no method given");
    if (cli.count("--jobs") > 0) jobs = parseJobs(f.jobs);
    // A variant of a suite (another association, another key) without a copy of its INI: the
    // extra keys follow the suite's [suite] localize_set (a sequence's own localize_set still
    // comes last); the command line in results.md records them.
    // Checked now by the rule every --set follows (core's applyOverride), so that a typo fails
    // before the first child runs.
    for (const auto& kv : f.localize_sets) {
        try {
            mrpt::config::CConfigFileMemory scratch;
            applyOverride(scratch, kv);
            checkSections(scratch, localizeSections(), "", {kv});
        } catch (const ConfigError& e) {
            throw std::invalid_argument(std::string("--localize-set: ") + e.what());
        }
        suite.localize_sets.push_back(kv);
    }
    command_line_ = "superloc-bench";
    for (const auto& a : args) command_line_ += " " + a;
}

std::string BenchApp::tool(const std::string& name) const {
    const std::string t = findTool(name, tools_dir);
    if (t.empty())
        throw std::runtime_error(name + " not found next to superloc-bench (" + tools_dir +
                                 "), in the build tree or on PATH");
    return t;
}

std::string BenchApp::prepare(const SequenceSpec& seq, const SequenceFiles& f, std::ostream& log) {
    const std::string logs = (fs::path(out_dir) / "logs").string();
    const auto step = [&](const std::vector<std::string>& argv, const std::string& what) {
        say(log, "  " + seq.name + ": " + what + ": " + joinCommand(argv));
        const ProcessResult p =
            runProcess(argv, logs + "/" + seq.name + "-" + what + ".log", suite.timeout_s);
        const std::string st = status(p, suite.timeout_s);
        return st == "ok" ? std::string()
                          : what + " " + st + " (see logs/" + seq.name + "-" + what + ".log)";
    };
    if (seq.kind == SequenceSpec::Kind::Sim) {
        if (!fresh && allExist({f.rawlog, f.gt_tum, f.gt_map, f.prior_map})) return "";
        if (auto e = step(simCommand(tool("superloc-sim"), seq, f.dir), "sim"); !e.empty())
            return e;
    } else {
        if (fresh || !fs::exists(f.rawlog))
            if (auto e = step(importCommand(tool("superloc-import"), seq, f.rawlog), "import");
                !e.empty())
                return e;
        if (fresh || !fs::exists(f.prior_map))
            if (auto e = step(mapCommand(tool("superloc-map"), f.rawlog, seq.gt, seq.prior_voxel,
                                         f.prior_map, seq.map_scans),
                              "prior-map");
                !e.empty())
                return e;
        if (fresh || !fs::exists(f.gt_map))
            if (auto e = step(
                    mapCommand(tool("superloc-map"), f.rawlog, seq.gt, seq.gt_map_voxel, f.gt_map),
                    "gt-map");
                !e.empty())
                return e;
    }
    for (const auto& p : {f.rawlog, f.gt_tum, f.gt_map, f.prior_map})
        if (!fs::exists(p)) return "missing " + p + " after preparing";
    return "";
}

RunRecord BenchApp::runOne(const SequenceSpec& seq, const SequenceFiles& f,
                           const std::string& method, const Trajectory& gt,
                           const PointCloud& gt_map, std::ostream& log,
                           std::vector<std::string>& plots_written) const {
    RunRecord r;
    r.sequence = seq.name;
    r.method = method;
    r.gt_length_m = pathLength(gt);
    const fs::path dir = fs::path(out_dir) / "runs" / seq.name / method;
    fs::remove_all(dir);
    fs::create_directories(dir);
    const auto argv =
        localizeCommand(tool("superloc-localize"), suite, seq, method, f, dir.string());
    say(log, "  " + seq.name + " / " + method + ": " + joinCommand(argv));
    const ProcessResult p = runProcess(argv, (dir / "localize.log").string(), suite.timeout_s);
    r.status = status(p, suite.timeout_s);
    r.wall_s = p.wall_s;
    r.peak_rss_mb = p.peak_rss_mb;
    try {
        const fs::path traj = dir / "trajectory.tum";
        if (!fs::exists(traj)) {
            r.status = r.status == "ok" ? "no trajectory" : r.status + "; no trajectory";
            return r;
        }
        const Trajectory est = io::loadTum(traj.string());
        PointCloud est_map;
        if (fs::exists(dir / "localized_map.pcd"))
            est_map = io::loadPointCloud((dir / "localized_map.pcd").string());
        eval::FrameLog frames;
        const bool has_frames = fs::exists(dir / "frames.csv");
        if (has_frames) frames = eval::loadFrameLog((dir / "frames.csv").string());
        r.result = eval::evaluate(est, gt, suite.eval, est_map.empty() ? nullptr : &est_map, &gt_map,
                            has_frames ? &frames : nullptr);
        const std::string stem = seq.name + "_" + method;
        const std::vector<double> g =
            has_frames ? minTranslationGamma(est, frames, suite.eval.assoc_tolerance)
                       : std::vector<double>{};
        writePlot(stem + "_top.svg",
                  trajectoryTopViewSvg(gt, est, g, seq.name + " / " + method + " (top view)"),
                  plots_written);
        if (has_frames && frames.has_gamma)
            writePlot(stem + "_gamma.svg",
                      gammaTimelineSvg(frames, 0.2, seq.name + " / " + method + ": γ"),
                      plots_written);
    } catch (const std::exception& e) {
        r.status = (r.status == "ok" ? "" : r.status + "; ") +
                   "evaluation failed: " + std::string(e.what()).substr(0, 200);
    }
    return r;
}

void BenchApp::checkLocalizeConfig() const {
    // superloc-localize itself loads the suite's configuration with each method and the suite's
    // overrides (--dump-config: nothing is run), so that an unknown method or a bad key stops the
    // suite before its first run, with the localizer's own one-line reason, rather than failing
    // every run of that method late with the reason in a per-run log.
    const std::string localize = findTool("superloc-localize", tools_dir);
    if (localize.empty()) return;  // every run says so (runOne)
    for (const auto& method : suite.methods) {
        std::vector<std::string> argv = {localize, suite.localize_config, "--method", method};
        for (const auto& s : suite.localize_sets) argv.insert(argv.end(), {"--set", s});
        argv.push_back("--dump-config");
        const std::string log = (fs::path(out_dir) / "logs" / ("check-" + method + ".log")).string();
        fs::remove(log);
        const ProcessResult p = runProcess(argv, log, suite.timeout_s);
        if (p.ok()) continue;
        std::string reason = status(p, suite.timeout_s), line;
        std::ifstream in(log);
        while (std::getline(in, line))
            if (!line.empty()) reason = line;  // the last line: the app's one-line error
        throw std::runtime_error(suite.path + ": method '" + method + "': " + reason);
    }
}

void BenchApp::writePlot(const std::string& name, const std::string& svg,
                         std::vector<std::string>& written) const {
    writeTextFile((fs::path(out_dir) / name).string(), svg);
    if (std::find(written.begin(), written.end(), name) == written.end()) written.push_back(name);
}

void BenchApp::say(std::ostream& log, const std::string& line) const {
    std::lock_guard<std::mutex> lock(log_mutex_);
    log << line << std::endl;
}

void BenchApp::writeResults() const {
    std::vector<std::string> seqs, meths = suite.methods;
    for (const auto& s : suite.sequences) seqs.push_back(s.name);
    char date[64];
    const std::time_t now = std::time(nullptr);
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    std::string preamble = "Produced by `" + command_line_ + "` on " + date + ".\n";
    if (jobs_used_ > 1)
        preamble += "\n" + std::to_string(jobs_used_) +
                    " runs at a time (--jobs) shared the machine's cores: the times (ms per frame, "
                    "wall) are higher than those of a run alone (--jobs 1).\n";
    std::vector<SeedGroup> groups;
    for (const auto& s : suite.sequences) {
        if (groups.empty() || groups.back().name != s.group) groups.push_back({s.group, {}});
        groups.back().members.push_back(s.name);
    }
    writeTextFile((fs::path(out_dir) / "results.md").string(),
                  resultsMarkdown(runs, seqs, meths, preamble, plots) + seedMeansMarkdown(runs, groups, meths));
    writeTextFile((fs::path(out_dir) / "results.json").string(),
                  resultsJson(runs, suite.path, jobs_used_));
}

int BenchApp::run(std::ostream& log) {
    if (help) {
        log << usage();
        return 0;
    }
    fs::create_directories(fs::path(out_dir) / "logs");
    checkLocalizeConfig();
    runs.clear();
    plots.clear();
    jobs_used_ = jobs > 0 ? jobs : availableCores();
    if (jobs_used_ > 1)
        say(log, "up to " + std::to_string(jobs_used_) + " runs at a time (--jobs; " +
                     std::to_string(availableCores()) +
                     " cores): they share the cores, so their times are higher than alone");
    // Each sequence's data and its runs' records and plots, filled in any order as the tasks
    // finish, reported in the suite's order (so the results are those of --jobs 1).
    struct Sequence {
        SequenceFiles files;
        std::string err;
        Trajectory gt;
        PointCloud gt_map;
        std::vector<std::optional<RunRecord>> runs;
        std::vector<std::vector<std::string>> plots;
        std::vector<std::string> f1_plots;
        size_t finished = 0;
    };
    const size_t n_meth = suite.methods.size();
    std::vector<Sequence> seqs(suite.sequences.size());
    for (auto& q : seqs) q.runs.resize(n_meth), q.plots.resize(n_meth);
    std::mutex results_mutex;  // guards seqs[*].runs/plots/f1_plots/finished, runs, plots
    // With results_mutex held: runs and plots from the records so far, then the result files.
    const auto publish = [&] {
        runs.clear();
        plots.clear();
        const auto addPlots = [&](const std::vector<std::string>& names) {
            for (const auto& n : names)
                if (std::find(plots.begin(), plots.end(), n) == plots.end()) plots.push_back(n);
        };
        for (const auto& q : seqs) {
            for (size_t k = 0; k < n_meth; ++k) {
                if (q.runs[k]) runs.push_back(*q.runs[k]);
                addPlots(q.plots[k]);
            }
            addPlots(q.f1_plots);
        }
        writeResults();
    };
    // With results_mutex held, once every run of sequence i has finished: its F1 curves.
    const auto sequenceDone = [&](size_t i) {
        std::vector<std::pair<std::string, eval::RobustnessCurve>> rp, rr;
        for (size_t k = 0; k < n_meth; ++k)
            if (const auto& r = seqs[i].runs[k]; r && r->result)
                rp.emplace_back(r->method, r->result->rp), rr.emplace_back(r->method, r->result->rr);
        const std::string& name = suite.sequences[i].name;
        if (drop_data) {
            std::error_code ec;
            for (const auto* f : {&seqs[i].files.rawlog, &seqs[i].files.gt_map, &seqs[i].files.prior_map})
                fs::remove(*f, ec);
            seqs[i].gt_map = PointCloud{};
        }
        if (!rp.empty()) {
            writePlot(name + "_f1_trans.svg", f1CurvesSvg(rp, false, name + ": F1 (translation RPE)"),
                      seqs[i].f1_plots);
            writePlot(name + "_f1_rot.svg", f1CurvesSvg(rr, true, name + ": F1 (rotation RPE)"),
                      seqs[i].f1_plots);
        }
    };
    // Keys: a sequence's preparation, then its runs in method order, then the next sequence:
    // with one job this is the order of the suite; with more, a sequence's runs go before the
    // preparation of later sequences as soon as its data is ready.
    TaskQueue queue(jobs_used_);
    for (size_t i = 0; i < seqs.size(); ++i) {
        const size_t key = i * (n_meth + 1);
        queue.add(key, [&, i, key] {
            Sequence& q = seqs[i];
            const SequenceSpec& seq = suite.sequences[i];
            q.files = sequenceFiles(seq, out_dir);
            fs::create_directories(q.files.dir);
            say(log, "[" + seq.name + "] preparing data");
            try {
                q.err = prepare(seq, q.files, log);
                if (q.err.empty())
                    q.gt = io::loadTum(q.files.gt_tum), q.gt_map = io::loadPointCloud(q.files.gt_map);
            } catch (const std::exception& e) {
                q.err = std::string(e.what()).substr(0, 200);
            }
            if (!q.err.empty()) {
                std::lock_guard<std::mutex> lock(results_mutex);
                for (size_t k = 0; k < n_meth; ++k) {
                    RunRecord r;
                    r.sequence = seq.name, r.method = suite.methods[k], r.status = "no data: " + q.err;
                    q.runs[k] = r;
                }
                publish();
                return;
            }
            // q's data is read-only from here on: the runs read it at the same time.
            for (size_t k = 0; k < n_meth; ++k)
                queue.add(key + 1 + k, [&, i, k] {
                    const Sequence& d = seqs[i];
                    const SequenceSpec& sq = suite.sequences[i];
                    std::vector<std::string> written;
                    RunRecord r = runOne(sq, d.files, suite.methods[k], d.gt, d.gt_map, log, written);
                    say(log, "  " + sq.name + " / " + suite.methods[k] + ": " + outcome(r));
                    std::lock_guard<std::mutex> lock(results_mutex);
                    seqs[i].runs[k] = std::move(r);
                    seqs[i].plots[k] = std::move(written);
                    if (++seqs[i].finished == n_meth) sequenceDone(i);
                    publish();
                });
        });
    }
    queue.run();
    publish();
    for (const auto& r : runs)
        if (!r.result) return 2;
    return 0;
}

}  // namespace superloc::app
