// The superloc-eval application (doc/evaluation.md): evaluates one run against ground truth.
//
//   superloc-eval --est TUM --gt TUM [--est-map F --gt-map F] [--frames CSV] [--json OUT]
//                 [--plots DIR] [--align] [--config INI] [--set eval.key=value]... [--dump-config]
#pragma once

#include <superloc/eval/eval_params.h>

#include <exception>
#include <ostream>
#include <string>
#include <vector>

namespace superloc::app {

class EvalApp {
 public:
    /// Parses the command line; throws std::invalid_argument (one line, naming the flag) or
    /// ConfigError on bad input.
    void initialize(const std::vector<std::string>& args);
    /// Runs and prints the Markdown summary (or --help / --dump-config text) to `out`; returns
    /// the process exit code. Throws std::runtime_error naming the file on unreadable input.
    int run(std::ostream& out);

    static std::string usage();

    std::string est_path, gt_path, est_map_path, gt_map_path, frames_path, json_path, plots_dir;
    eval::EvalParams params;
    bool help = false, dump_config = false;
};


}  // namespace superloc::app
