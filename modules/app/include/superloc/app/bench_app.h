// The superloc-bench application (doc/evaluation.md): runs a suite of sequences x methods through
// the other apps (as child processes found next to this one), evaluates every run and writes
// DIR/results.md, DIR/results.json and DIR/*.svg.
//
//   superloc-bench SUITE.ini --out DIR [--data DIR] [--tools DIR] [--sequences "a b"]
//                  [--methods "m1 m2"] [--localize-set S.K=V]... [--fresh] [--drop-data] [--jobs N]
//                  [--plan | --run ID | --collect]
// A suite is a plan of runs (bench_plan.h): a data run per sequence, then a localization run
// per sequence and method. Without --plan/--run/--collect the plan runs here, up to --jobs N
// children at once; a sequence's runs start once its data is ready; the results are those of
// --jobs 1, in the same order; only the measured times differ (the runs share cores). --plan
// prints one shell command per run for another scheduler (GNU parallel, a Slurm array), --run
// executes one, --collect evaluates the runs' folders and writes the results: the same code as
// the one-machine path, which is plan, run, collect in one process.
#pragma once

#include <superloc/app/bench_plan.h>
#include <superloc/app/bench_report.h>
#include <superloc/app/bench_run_status.h>
#include <superloc/app/suite.h>

#include <mutex>
#include <ostream>
#include <string>
#include <vector>

namespace superloc::app {

class BenchApp {
 public:
    enum class Mode {
        All,      ///< plan, run and collect here
        Plan,     ///< --plan: write DIR/plan.json, print a command per run
        Run,      ///< --run ID: one run of the plan
        Collect,  ///< --collect: the results from the runs' folders
    };

    /// Parses the command line and the suite file; throws std::invalid_argument or ConfigError
    /// with a one-line reason.
    void initialize(const std::vector<std::string>& args);
    /// Does what the mode says, printing progress lines to `log` (whole lines, also from
    /// parallel runs); --plan prints its commands to `log` and its summary to `notes`.
    /// Returns 0 when every run produced a trajectory (--run: when its child succeeded), 2 when
    /// some did not or are missing (the results are written either way).
    int run(std::ostream& log, std::ostream& notes);
    int run(std::ostream& log) { return run(log, log); }
    static std::string usage();

    SuiteSpec suite;
    std::string out_dir, data_dir, tools_dir;
    bool fresh = false, help = false;
    bool drop_data = false;  ///< --drop-data: delete a sequence's rawlog and maps after its runs
    unsigned jobs = 0;               ///< children at once (--jobs); 0: one per available core
    Mode mode = Mode::All;
    std::string run_key;             ///< --run: a run's ID or index
    /// The superloc-bench executable the plan's commands run (default: this process's)
    std::string bench_path;
    std::string version = "unknown";  ///< this build's version, written into each status file
    std::vector<RunRecord> runs;     ///< filled by run(), sequence by sequence, methods in order
    std::vector<std::string> plots;  ///< SVG files written (relative to out_dir)

 private:
    struct Sequence;
    /// Plan, run and collect (mode All), or collect only: the same tasks, sequence by sequence.
    int execute(std::ostream& log, bool collect_only);
    int printPlan(std::ostream& out, std::ostream& notes) const;
    int runPlanned(std::ostream& log) const;
    /// data:SEQ: simulates, or imports and maps, sequence i unless its data is complete (under
    /// the sequence's lock); writes its status and, last, the completion marker. "" or why not.
    std::string runData(size_t i, std::ostream& log) const;
    std::string prepare(const SequenceSpec& seq, const SequenceFiles& f, std::ostream& log,
                        int& exit_code) const;
    /// Sequence i's data: "" when complete (with `gt_only`, its ground truth: what --collect
    /// reads), else why not: its data run's failure, or (`missing`) that it has not finished or
    /// its files changed since.
    std::string dataState(size_t i, bool gt_only, bool& missing) const;
    /// SEQ/METHOD: the localize child of sequence i and method k; writes its status.json.
    RunStatus runLocalize(size_t i, size_t k, std::ostream& log) const;
    /// A localization run's record from its folder: its status file, evaluated against the GT;
    /// the plots it wrote are added to `plots_written`.
    RunRecord collectRun(size_t i, size_t k, const Trajectory& gt, const PointCloud& gt_map,
                         std::vector<std::string>& plots_written) const;
    std::string runDir(size_t i, size_t k) const;
    /// The plan's shell command of run `id`.
    std::string runCommand(const std::string& id) const;
    /// Throws std::invalid_argument naming `flag` when DIR/plan.json is missing or another plan.
    void checkPlanFile(const std::string& flag) const;
    void savePlan() const;
    std::string tool(const std::string& name) const;
    /// Runs superloc-localize --dump-config with each method and the suite's overrides; throws
    /// std::runtime_error with its one-line reason when one fails (before any run starts).
    void checkLocalizeConfig() const;
    void writeResults() const;
    /// Writes DIR/name and adds name to `written`.
    void writePlot(const std::string& name, const std::string& svg,
                   std::vector<std::string>& written) const;
    /// Writes a whole line to `log` (runs in parallel print through it).
    void say(std::ostream& log, const std::string& line) const;
    std::vector<PlannedRun> plan_;
    std::string stamp_;                     ///< configStamp of the suite and overrides
    std::vector<std::string> plan_args_;    ///< the flags that shape the plan, for its commands
    unsigned jobs_used_ = 1;
    bool collected_ = false;
    std::string command_line_;
    mutable std::mutex log_mutex_;
};

}  // namespace superloc::app
