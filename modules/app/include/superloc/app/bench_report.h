// The benchmark suite's tables (paper Table I shape) and JSON (doc/evaluation.md).
#pragma once

#include <superloc/eval/evaluation.h>

#include <optional>
#include <string>
#include <vector>

namespace superloc::app {

/// One (sequence, method) run of a suite.
struct RunRecord {
    std::string sequence, method;
    std::string status = "ok";  ///< "ok", or why not: "exit 3", "timeout", "no trajectory", ...
    std::optional<eval::EvalResult> result;  ///< evaluated (also for a failed run that left poses)
    double wall_s = 0;                 ///< [s] wall time of the localize process
    double peak_rss_mb = 0;            ///< [MiB]
    double gt_length_m = 0;            ///< [m] path length of the sequence's GT
    bool missing = false;  ///< --collect found no run of it (or its data never ran), or a stale one
    std::string host;      ///< the machine that ran it
    std::string version;   ///< the superloc-bench build that ran it
};

/// results.md: one table per metric (rows = methods, columns = sequences, like the paper's
/// Table I), best value per column in bold, and a status list of runs that did not finish.
/// `preamble` (command, commit, date) is written under the title; `plots` (file names relative
/// to results.md) are embedded as images at the end.
std::string resultsMarkdown(const std::vector<RunRecord>& runs,
                            const std::vector<std::string>& sequences,
                            const std::vector<std::string>& methods, const std::string& preamble,
                            const std::vector<std::string>& plots = {});

/// A suite sequence run with several seeds (SuiteSpec `seeds`): its name and its runs' sequences.
struct SeedGroup {
    std::string name;
    std::vector<std::string> members;
};

/// The mean over seeds of ATE RMSE and map outliers per group and method, with the seeds'
/// range, for the groups of more than one seed ("" when there are none). A group's mean counts
/// only finished runs; a group with a run that did not finish says how many it counts.
std::string seedMeansMarkdown(const std::vector<RunRecord>& runs, const std::vector<SeedGroup>& groups,
                              const std::vector<std::string>& methods);

/// results.json: {"suite", "jobs", "runs": [...]} with every metric (no curves) per run; `jobs`
/// runs were run at a time (superloc-bench --jobs: above 1 the times were measured on shared
/// cores); null when not known (--collect: another scheduler ran them).
std::string resultsJson(const std::vector<RunRecord>& runs, const std::string& suite_path,
                        std::optional<unsigned> jobs = 1);

/// Path length [m] of a trajectory (sum of consecutive translation distances).
double pathLength(const Trajectory& traj);

}  // namespace superloc::app
