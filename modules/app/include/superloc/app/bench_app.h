// The superloc-bench application (doc/evaluation.md): runs a suite of sequences x methods through
// the other apps (as child processes found next to this one), evaluates every run and writes
// DIR/results.md, DIR/results.json and DIR/*.svg.
//
//   superloc-bench SUITE.ini --out DIR [--data DIR] [--tools DIR] [--sequences "a b"]
//                  [--methods "m1 m2"] [--fresh] [--drop-data] [--jobs N]
// With --jobs N, up to N children (a sequence's preparation, or one localize run and its
// evaluation) run at once; a sequence's runs start once its data is ready. The results are
// those of --jobs 1, in the same order; only the measured times differ (the runs share cores).
#pragma once

#include <superloc/app/bench_report.h>
#include <superloc/app/suite.h>

#include <mutex>
#include <ostream>
#include <string>
#include <vector>

namespace superloc::app {

class BenchApp {
 public:
    /// Parses the command line and the suite file; throws std::invalid_argument or ConfigError
    /// with a one-line reason.
    void initialize(const std::vector<std::string>& args);
    /// Runs the suite, printing one progress line per step to `log` (whole lines, also from
    /// parallel runs). Returns 0 when every run produced a trajectory, 2 when some did not
    /// (results are written either way).
    int run(std::ostream& log);
    static std::string usage();

    SuiteSpec suite;
    std::string out_dir, data_dir, tools_dir;
    bool fresh = false, help = false;
    bool drop_data = false;  ///< --drop-data: delete a sequence's rawlog and maps after its runs
    unsigned jobs = 0;               ///< children at once (--jobs); 0: one per available core
    std::vector<RunRecord> runs;     ///< filled by run(), sequence by sequence, methods in order
    std::vector<std::string> plots;  ///< SVG files written (relative to out_dir)

 private:
    /// Simulates or imports + maps a sequence unless its files exist; "" or the failure.
    std::string prepare(const SequenceSpec& seq, const SequenceFiles& f, std::ostream& log);
    /// Localizes and evaluates one run; the plots it wrote are added to `plots_written`.
    RunRecord runOne(const SequenceSpec& seq, const SequenceFiles& f, const std::string& method,
                     const Trajectory& gt, const PointCloud& gt_map, std::ostream& log,
                     std::vector<std::string>& plots_written) const;
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
    unsigned jobs_used_ = 1;
    std::string command_line_;
    mutable std::mutex log_mutex_;
};

}  // namespace superloc::app
