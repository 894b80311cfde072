#include <CLI/CLI.hpp>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/app/bench_app.h>
#include <superloc/app/bench_plan.h>
#include <superloc/app/bench_run_status.h>
#include <superloc/app/command_line.h>
#include <superloc/app/ini_sections.h>
#include <superloc/app/process.h>
#include <superloc/app/report_plots.h>
#include <superloc/app/task_queue.h>
#include <superloc/core/config.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
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
    bool plan = false, collect = false;
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
    cli.add_option("--sequences", f.only_seq, "run only these sequences of the suite (NAME of a [seq.NAME] with seeds: all of them)")->type_name("\"a b\"");
    cli.add_option("--methods", f.only_meth, "run only these methods of the suite")->type_name("\"m1 m2\"");
    cli.add_flag("--fresh", app.fresh, "regenerate simulated/imported data even if present");
    cli.add_flag("--drop-data", app.drop_data,
                 "delete a sequence's rawlog and maps once all its runs are evaluated (a big suite's\n"
                 "simulated data take ~1.4 GB per 150 s sequence; its GT trajectory stays)");
    cli.add_option("--localize-set", f.localize_sets,
                   "one more --set for every superloc-localize run (after the suite's [suite] keys), e.g.\n"
                   "--localize-set association.kind=voxel (repeatable)")
        ->type_name("SECTION.KEY=VALUE");
    cli.add_option("--jobs", f.jobs,
                   "children run at once (default: the number of cores): a sequence's preparation,\n"
                   "or one localize run and its evaluation; the results are those of --jobs 1, but\n"
                   "the runs share the cores, so their times (ms per frame, wall) are higher; with\n"
                   "--collect, runs evaluated at once")
        ->type_name("N");
    cli.add_flag("--plan", f.plan,
                 "do not run: write DIR/plan.json and print one shell command per run for another\n"
                 "scheduler (GNU parallel, a Slurm array): the data runs first, then each localize\n"
                 "run after its data run; the summary (index ranges) goes to stderr");
    cli.add_option("--run", app.run_key,
                   "execute one run of DIR/plan.json into DIR: data:SEQ, SEQ/METHOD or its index\n"
                   "(--plan lists them); exit 0 when its child succeeded, 2 when it failed")
        ->type_name("ID");
    cli.add_flag("--collect", f.collect,
                 "do not run: write the results from the runs' folders (any machine may have run\n"
                 "them), naming each missing or failed run; exit 2 when a run is missing");
    cli.footer(
        "Split over machines (doc/evaluation.md#runs-split-for-a-scheduler):\n"
        "  superloc-bench SUITE.ini --out DIR --plan | parallel -j 8   (or --sshloginfile ...)\n"
        "  superloc-bench SUITE.ini --out DIR --collect\n");
}

/// Sequence i's data run ID.
std::string dataId(const SuiteSpec& suite, size_t i) { return "data:" + suite.sequences[i].name; }

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
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
    // The steps of a split run exclude each other and the flags that only make sense in one
    // process: checked before the suite is read, so the error names the flags.
    std::vector<std::string> steps;
    for (const char* flag : {"--plan", "--run", "--collect"})
        if (cli.count(flag) > 0) steps.push_back(flag);
    if (steps.size() > 1)
        throw std::invalid_argument(steps[0] + " and " + steps[1] +
                                    ": give one step at a time (--plan, then --run ID for each of "
                                    "its runs, then --collect)");
    mode = f.plan ? Mode::Plan : cli.count("--run") > 0 ? Mode::Run : f.collect ? Mode::Collect : Mode::All;
    const std::string step = steps.empty() ? "" : steps[0];
    if (cli.count("--jobs") > 0 && (mode == Mode::Plan || mode == Mode::Run))
        throw std::invalid_argument("--jobs: not with " + step +
                                    " (the scheduler that runs the plan's commands decides how many "
                                    "run at once, e.g. parallel -j N)");
    if (fresh && mode != Mode::All)
        throw std::invalid_argument("--fresh: not with " + step + " (to prepare a sequence again, "
                                    "delete DIR/data/SEQ before --run data:SEQ)");
    if (drop_data && (mode == Mode::Plan || mode == Mode::Run))
        throw std::invalid_argument("--drop-data: not with " + step +
                                    " (a run cannot know when its sequence's last run ends); give "
                                    "it to --collect");
    if (tools_dir.empty()) tools_dir = selfDir();
    if (bench_path.empty()) bench_path = selfExe();
    suite = loadSuite(suite_path, data_dir);
    if (seq_given) {
        std::vector<SequenceSpec> keep;
        for (const auto& name : splitWords(only_seq)) {
            bool found = false;
            // A sequence (NAME_sN of a seeded one), or a suite section: every seed of it.
            for (const auto& s : suite.sequences)
                if (s.name == name || s.group == name) {
                    found = true;
                    if (std::none_of(keep.begin(), keep.end(), [&](const SequenceSpec& k) { return k.name == s.name; }))
                        keep.push_back(s);
                }
            if (!found)
                throw std::invalid_argument("--sequences: '" + name + "' is not in " + suite_path +
                                            " (a [seq.NAME] section, or NAME_sN for one of its seeds)");
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
    // The plan, and the flags its commands repeat so that each run sees the same suite.
    plan_ = planRuns(suite);
    stamp_ = configStamp(readText(suite_path), readText(suite.localize_config), suite.localize_sets);
    plan_args_.clear();
    const auto absolute = [](const std::string& p) { return fs::absolute(p).lexically_normal().string(); };
    if (cli.count("--data") > 0) plan_args_.insert(plan_args_.end(), {"--data", absolute(data_dir)});
    if (cli.count("--tools") > 0) plan_args_.insert(plan_args_.end(), {"--tools", absolute(tools_dir)});
    if (seq_given) plan_args_.insert(plan_args_.end(), {"--sequences", only_seq});
    if (meth_given) plan_args_.insert(plan_args_.end(), {"--methods", only_meth});
    for (const auto& kv : f.localize_sets) plan_args_.insert(plan_args_.end(), {"--localize-set", kv});
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

std::string BenchApp::prepare(const SequenceSpec& seq, const SequenceFiles& f, std::ostream& log,
                              int& exit_code) const {
    const std::string logs = (fs::path(out_dir) / "logs").string();
    const auto step = [&](const std::vector<std::string>& argv, const std::string& what) {
        say(log, "  " + seq.name + ": " + what + ": " + joinCommand(argv));
        const ProcessResult p =
            runProcess(argv, logs + "/" + seq.name + "-" + what + ".log", suite.timeout_s);
        exit_code = p.exit_code;
        const std::string st = status(p, suite.timeout_s);
        return st == "ok" ? std::string()
                          : what + " " + st + " (see logs/" + seq.name + "-" + what + ".log)";
    };
    // Every step again: a step that was stopped part way may have left a truncated file.
    if (seq.kind == SequenceSpec::Kind::Sim) {
        if (auto e = step(simCommand(tool("superloc-sim"), seq, f.dir), "sim"); !e.empty())
            return e;
    } else {
        if (auto e = step(importCommand(tool("superloc-import"), seq, f.rawlog), "import"); !e.empty())
            return e;
        if (auto e = step(mapCommand(tool("superloc-map"), f.rawlog, seq.gt, seq.prior_voxel,
                                     f.prior_map, seq.map_scans),
                          "prior-map");
            !e.empty())
            return e;
        if (auto e = step(mapCommand(tool("superloc-map"), f.rawlog, seq.gt, seq.gt_map_voxel, f.gt_map),
                          "gt-map");
            !e.empty())
            return e;
    }
    for (const auto& p : {f.rawlog, f.gt_tum, f.gt_map, f.prior_map})
        if (!fs::exists(p)) return "missing " + p + " after preparing";
    return "";
}

std::string BenchApp::runData(size_t i, std::ostream& log) const {
    const SequenceSpec& seq = suite.sequences[i];
    const SequenceFiles f = sequenceFiles(seq, out_dir);
    fs::create_directories(f.dir);
    fs::create_directories(fs::path(out_dir) / "logs");
    // One preparation of a sequence at a time (a plan's command of each localize run prepares
    // its data first); whoever comes second finds the data complete.
    const DataLock lock(f.dir);
    if (lock.waited()) say(log, "  " + seq.name + ": waited for another run preparing its data");
    if (!fresh && dataIncomplete(f).empty()) {
        say(log, "  " + seq.name + ": data complete, reused (" + f.dir + "/complete)");
        return "";
    }
    unmarkDataComplete(f);
    RunStatus st;
    st.id = dataId(suite, i);
    st.config = stamp_;
    const auto t0 = std::chrono::steady_clock::now();
    std::string err;
    try {
        err = prepare(seq, f, log, st.exit_code);
    } catch (const std::exception& e) {
        err = std::string(e.what()).substr(0, 200);
        st.exit_code = -1;
    }
    st.status = err.empty() ? "ok" : err;
    st.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    st.version = version, st.host = hostName(), st.finished = utcNow();
    saveRunStatus(f.dir, st);
    if (err.empty()) markDataComplete(f);  // last: the data counts from here on
    return err;
}

std::string BenchApp::dataState(size_t i, bool gt_only, bool& missing) const {
    const SequenceFiles f = sequenceFiles(suite.sequences[i], out_dir);
    const std::string why = dataIncomplete(f, gt_only);
    missing = false;
    if (why.empty()) return "";
    const auto st = loadRunStatus(f.dir);
    if (st && st->status != "ok") return st->status;  // it failed: the same reason as in one process
    missing = true;
    return dataId(suite, i) + (st ? " is not complete any more (" : " has not finished (") + why + ")";
}

std::string BenchApp::runDir(size_t i, size_t k) const {
    return (fs::path(out_dir) / "runs" / suite.sequences[i].name / suite.methods[k]).string();
}

RunStatus BenchApp::runLocalize(size_t i, size_t k, std::ostream& log) const {
    const SequenceSpec& seq = suite.sequences[i];
    const std::string& method = suite.methods[k];
    const fs::path dir = runDir(i, k);
    fs::remove_all(dir);
    fs::create_directories(dir);
    const auto argv = localizeCommand(tool("superloc-localize"), suite, seq, method,
                                      sequenceFiles(seq, out_dir), dir.string());
    say(log, "  " + seq.name + " / " + method + ": " + joinCommand(argv));
    const ProcessResult p = runProcess(argv, (dir / "localize.log").string(), suite.timeout_s);
    RunStatus st;
    st.id = seq.name + "/" + method;
    st.config = stamp_;
    st.status = status(p, suite.timeout_s);
    st.exit_code = p.exit_code;
    st.wall_s = p.wall_s;
    st.peak_rss_mb = p.peak_rss_mb;
    st.version = version, st.host = hostName(), st.finished = utcNow();
    saveRunStatus(dir.string(), st);
    return st;
}

RunRecord BenchApp::collectRun(size_t i, size_t k, const Trajectory& gt, const PointCloud& gt_map,
                               std::vector<std::string>& plots_written) const {
    const SequenceSpec& seq = suite.sequences[i];
    const std::string& method = suite.methods[k];
    RunRecord r;
    r.sequence = seq.name;
    r.method = method;
    r.gt_length_m = pathLength(gt);
    const fs::path dir = runDir(i, k);
    const std::string rel = "runs/" + seq.name + "/" + method;
    try {
        const auto st = loadRunStatus(dir.string());
        r.missing = !st || st->config != stamp_;
        if (!st) {
            r.status = "missing: no " + rel + "/status.json (not run, still running, or killed)";
            return r;
        }
        if (st->config != stamp_) {
            r.status = "stale: " + rel + " ran with another suite, localize INI or --localize-set";
            return r;
        }
        r.status = st->status, r.wall_s = st->wall_s, r.peak_rss_mb = st->peak_rss_mb;
        r.host = st->host, r.version = st->version;
    } catch (const std::exception& e) {
        r.status = std::string("unreadable status: ") + e.what();
        return r;
    }
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
    if (localize.empty()) return;  // every run says so (runLocalize)
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
    if (collected_) {
        // Where and by which builds the runs ran: their times depend on those machines and on
        // what else ran there, which the scheduler decided.
        std::map<std::string, size_t> hosts, builds;
        for (const auto& r : runs) {
            if (!r.host.empty()) ++hosts[r.host];
            if (!r.version.empty()) ++builds[r.version];
        }
        const auto list = [](const std::map<std::string, size_t>& m) {
            std::string s;
            for (const auto& [name, n] : m)
                s += (s.empty() ? "" : ", ") + name + ": " + std::to_string(n) + " runs";
            return s.empty() ? std::string("none") : s;
        };
        preamble += "\nCollected (--collect) from runs made one by one (--run); hosts " + list(hosts) +
                    "; builds " + list(builds) +
                    ". Their times (ms per frame, wall) depend on those machines and on what ran "
                    "beside each run.\n";
    } else if (jobs_used_ > 1) {
        preamble += "\n" + std::to_string(jobs_used_) +
                    " runs at a time (--jobs) shared the machine's cores: the times (ms per frame, "
                    "wall) are higher than those of a run alone (--jobs 1).\n";
    }
    std::vector<SeedGroup> groups;
    for (const auto& s : suite.sequences) {
        if (groups.empty() || groups.back().name != s.group) groups.push_back({s.group, {}});
        groups.back().members.push_back(s.name);
    }
    writeTextFile((fs::path(out_dir) / "results.md").string(),
                  resultsMarkdown(runs, seqs, meths, preamble, plots) + seedMeansMarkdown(runs, groups, meths));
    writeTextFile((fs::path(out_dir) / "results.json").string(),
                  resultsJson(runs, suite.path,
                              collected_ ? std::nullopt : std::optional<unsigned>(jobs_used_)));
}

std::string BenchApp::runCommand(const std::string& id) const {
    std::vector<std::string> argv = {bench_path, fs::absolute(suite.path).lexically_normal().string(),
                                     "--out", fs::absolute(out_dir).lexically_normal().string()};
    argv.insert(argv.end(), plan_args_.begin(), plan_args_.end());
    argv.insert(argv.end(), {"--run", id});
    return joinCommand(argv);
}

void BenchApp::savePlan() const {
    PlanFile p{stamp_, {}};
    std::vector<std::string> commands;
    for (const auto& r : plan_) p.ids.push_back(r.id), commands.push_back(runCommand(r.id));
    fs::create_directories(out_dir);
    savePlanFile((fs::path(out_dir) / "plan.json").string(), p, suite.path, version, commands);
}

void BenchApp::checkPlanFile(const std::string& flag) const {
    const std::string path = (fs::path(out_dir) / "plan.json").string();
    const auto p = loadPlanFile(path);
    if (!p)
        throw std::invalid_argument(flag + ": " + path + " does not exist: make the plan first "
                                    "(superloc-bench SUITE.ini --out " + out_dir + " --plan)");
    std::vector<std::string> ids;
    for (const auto& r : plan_) ids.push_back(r.id);
    if (p->ids != ids)
        throw std::invalid_argument(
            flag + ": " + path + " plans other runs (" + std::to_string(p->ids.size()) +
            ") than this command line (" + std::to_string(ids.size()) +
            "): give the plan's --sequences / --methods, or --plan again");
    if (p->config != stamp_)
        throw std::invalid_argument(flag + ": " + path +
                                    " was planned with another suite, localize INI or --localize-set "
                                    "(--plan again)");
}

int BenchApp::printPlan(std::ostream& out, std::ostream& notes) const {
    fs::create_directories(fs::path(out_dir) / "logs");
    checkLocalizeConfig();
    savePlan();
    size_t n_data = 0;
    for (const auto& r : plan_) {
        std::string line = runCommand(r.id) + "  # " + std::to_string(r.index) + " " + r.id;
        if (!r.isData()) {
            // Its data run first: it returns at once when the data is complete, and waits for
            // another process preparing it (GNU parallel starts lines in order, not after the
            // ones before have finished).
            const PlannedRun& d = plan_[r.sequence];
            line = runCommand(d.id) + " && " + line + " (after " + d.id + " = " + std::to_string(d.index) + ")";
        }
        n_data += r.isData();
        out << line << "\n";
    }
    out.flush();
    const auto range = [](size_t a, size_t b) {
        return a + 1 == b ? std::to_string(a) : std::to_string(a) + "-" + std::to_string(b - 1);
    };
    notes << "superloc-bench: " << plan_.size() << " runs in " << (fs::path(out_dir) / "plan.json").string()
          << ": data runs " << range(0, n_data) << " (data:SEQ), localization runs "
          << range(n_data, plan_.size()) << " (SEQ/METHOD, each after its data run; Slurm: --array="
          << range(0, n_data) << " then --array=" << range(n_data, plan_.size())
          << " --run $SLURM_ARRAY_TASK_ID); then --collect\n";
    return 0;
}

int BenchApp::runPlanned(std::ostream& log) const {
    checkPlanFile("--run");
    const PlannedRun& r = findRun(plan_, run_key);
    if (r.isData()) {
        say(log, "[" + r.id + "] preparing data");
        const std::string err = runData(r.sequence, log);
        say(log, "  " + r.id + ": " + (err.empty() ? std::string("ok") : err));
        return err.empty() ? 0 : 2;
    }
    const PlannedRun& d = plan_[r.sequence];
    bool missing = false;
    if (const std::string state = dataState(r.sequence, false, missing); !state.empty()) {
        throw std::runtime_error("--run " + r.id + ": its data is not ready (" + state + "): run " + d.id +
                                 " (" + std::to_string(d.index) + ") first");
    }
    fs::create_directories(fs::path(out_dir) / "logs");
    const RunStatus st = runLocalize(r.sequence, *r.method, log);
    char wall[32];
    std::snprintf(wall, sizeof wall, "%.1f", st.wall_s);
    say(log, "  " + r.id + ": " + st.status + " (" + wall + " s; --collect evaluates it)");
    return st.status == "ok" ? 0 : 2;
}

// Each sequence's data and its runs' records and plots, filled in any order as the tasks
// finish, reported in the suite's order (so the results are those of --jobs 1).
struct BenchApp::Sequence {
    SequenceFiles files;
    std::string err;
    Trajectory gt;
    PointCloud gt_map;
    std::vector<std::optional<RunRecord>> runs;
    std::vector<std::vector<std::string>> plots;
    std::vector<std::string> f1_plots;
    size_t finished = 0;
};

int BenchApp::execute(std::ostream& log, bool collect_only) {
    collected_ = collect_only;
    fs::create_directories(fs::path(out_dir) / "logs");
    if (!collect_only) {
        checkLocalizeConfig();
        savePlan();
    }
    runs.clear();
    plots.clear();
    jobs_used_ = jobs > 0 ? jobs : availableCores();
    if (jobs_used_ > 1 && !collect_only)
        say(log, "up to " + std::to_string(jobs_used_) + " runs at a time (--jobs; " +
                     std::to_string(availableCores()) +
                     " cores): they share the cores, so their times are higher than alone");
    const size_t n_meth = suite.methods.size();
    std::vector<Sequence> seqs(suite.sequences.size());
    for (auto& q : seqs) q.runs.resize(n_meth), q.plots.resize(n_meth);
    std::mutex results_mutex;  // guards seqs[*].runs/plots/f1_plots/finished, runs, plots, sharing
    // Per data folder, the sequences that have not finished yet (sequences that simulate the same
    // data share it): --drop-data removes it when the last of them is done.
    std::map<std::string, size_t> sharing;
    for (const auto& q : suite.sequences) ++sharing[sequenceFiles(q, out_dir).dir];
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
        if (drop_data && --sharing[sequenceFiles(suite.sequences[i], out_dir).dir] == 0) {
            std::error_code ec;
            unmarkDataComplete(seqs[i].files);
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
    // Keys: a sequence's data, then its runs in method order, then the next sequence: with one
    // job this is the order of the suite; with more, a sequence's runs go before the data of
    // later sequences as soon as its data is ready. Collecting runs the same tasks without the
    // children: the data's state, then each run's folder evaluated.
    TaskQueue queue(jobs_used_);
    for (size_t i = 0; i < seqs.size(); ++i) {
        const size_t key = i * (n_meth + 1);
        queue.add(key, [&, i, key] {
            Sequence& q = seqs[i];
            const SequenceSpec& seq = suite.sequences[i];
            q.files = sequenceFiles(seq, out_dir);
            if (!collect_only) say(log, "[" + seq.name + "] preparing data");
            bool missing = false;
            try {
                q.err = collect_only ? dataState(i, true, missing) : runData(i, log);
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
                    r.missing = missing;
                    if (collect_only) say(log, "  " + seq.name + " / " + r.method + ": " + r.status);
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
                    if (!collect_only) runLocalize(i, k, log);
                    std::vector<std::string> written;
                    RunRecord r = collectRun(i, k, d.gt, d.gt_map, written);
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
    int code = 0;
    std::vector<std::string> missing, failed;
    for (const auto& r : runs) {
        if (!r.result) code = 2;
        if (r.missing)
            missing.push_back(r.sequence + "/" + r.method);
        else if (r.status != "ok")
            failed.push_back(r.sequence + "/" + r.method);
    }
    if (collect_only) {
        const auto names = [](const std::vector<std::string>& v) {
            std::string s;
            for (const auto& n : v) s += (s.empty() ? "" : " ") + n;
            return s;
        };
        std::string line = "collected " + std::to_string(runs.size() - missing.size()) + " of " +
                           std::to_string(runs.size()) + " runs into " + out_dir + "/results.md";
        if (!failed.empty()) line += "; failed: " + names(failed);
        if (!missing.empty()) line += "; missing: " + names(missing) + " (--run each, then --collect again)";
        say(log, line);
    }
    return code;
}

int BenchApp::run(std::ostream& log, std::ostream& notes) {
    if (help) {
        log << usage();
        return 0;
    }
    switch (mode) {
        case Mode::Plan:
            return printPlan(log, notes);
        case Mode::Run:
            return runPlanned(log);
        case Mode::Collect:
            checkPlanFile("--collect");
            return execute(log, true);
        case Mode::All:
            break;
    }
    return execute(log, false);
}

}  // namespace superloc::app
