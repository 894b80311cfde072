// The superloc-bench application (doc/evaluation.md): runs a suite of sequences x methods through
// the other apps (as child processes found next to this one), evaluates every run and writes
// DIR/results.md, DIR/results.json and DIR/*.svg.
//
//   superloc-bench SUITE.ini --out DIR [--data DIR] [--tools DIR] [--sequences "a b"]
//                  [--methods "m1 m2"] [--fresh]
#pragma once

#include <superloc/app/bench_report.h>
#include <superloc/app/suite.h>

#include <ostream>
#include <string>
#include <vector>

namespace superloc::app {

class BenchApp {
 public:
    /// Parses the command line and the suite file; throws std::invalid_argument or ConfigError
    /// with a one-line reason.
    void initialize(const std::vector<std::string>& args);
    /// Runs the suite, printing one progress line per step to `log`. Returns 0 when every run
    /// produced a trajectory, 2 when some did not (results are written either way).
    int run(std::ostream& log);
    static std::string usage();

    SuiteSpec suite;
    std::string out_dir, data_dir, tools_dir;
    bool fresh = false, help = false;
    std::vector<RunRecord> runs;     ///< filled by run()
    std::vector<std::string> plots;  ///< SVG files written (relative to out_dir)

 private:
    /// Simulates or imports + maps a sequence unless its files exist; "" or the failure.
    std::string prepare(const SequenceSpec& seq, const SequenceFiles& f, std::ostream& log);
    RunRecord runOne(const SequenceSpec& seq, const SequenceFiles& f, const std::string& method,
                     const Trajectory& gt, const PointCloud& gt_map, std::ostream& log);
    std::string tool(const std::string& name) const;
    void writeResults() const;
    /// Writes DIR/name and remembers it for results.md.
    void writePlot(const std::string& name, const std::string& svg);
    std::string command_line_;
};

}  // namespace superloc::app
