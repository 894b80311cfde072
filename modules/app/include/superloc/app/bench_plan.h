// A benchmark suite split into runs that another scheduler can execute one by one
// (superloc-bench --plan / --run / --collect, doc/evaluation.md#runs-split-for-a-scheduler).
//
// A suite of S sequences and M methods has S data runs ("data:SEQ": simulate, or import and map)
// then S x M localization runs ("SEQ/METHOD"), numbered 0 .. S + S M - 1 in that order (the
// index of a Slurm array task). A localization run needs its sequence's data run. Each run
// leaves `status.json` in its folder (DIR/data/SEQ, DIR/runs/SEQ/METHOD); a data run's files
// count only once `complete`, written last, lists them with their sizes.
#pragma once

#include <superloc/app/suite.h>

#include <optional>
#include <string>
#include <vector>

namespace superloc::app {

/// One run of a suite's plan.
struct PlannedRun {
    size_t index = 0;               ///< position in the plan (data runs first)
    std::string id;                 ///< "data:SEQ" or "SEQ/METHOD"
    size_t sequence = 0;            ///< into SuiteSpec::sequences
    std::optional<size_t> method;   ///< into SuiteSpec::methods; none for a data run
    bool isData() const { return !method.has_value(); }
};

/// The runs of `suite`: a data run per sequence in the suite's order, then the localization runs,
/// sequence by sequence, methods in order.
std::vector<PlannedRun> planRuns(const SuiteSpec& suite);

/// The run `key` names: an ID ("data:SEQ", "SEQ/METHOD") or an index. Throws
/// std::invalid_argument naming --run and the valid range when there is none.
const PlannedRun& findRun(const std::vector<PlannedRun>& plan, const std::string& key);

/// Identifies what a localization run's result depends on besides its data: FNV-1a 64 (hex)
/// of the suite file's text, the localize configuration's text and the localize overrides of
/// the command line. Each status file carries it, so that --collect can tell a run made with
/// this configuration from one an earlier configuration left in the same folder.
std::string configStamp(const std::string& suite_text, const std::string& localize_config_text,
                        const std::vector<std::string>& localize_sets);

/// DIR/plan.json: what `--run` and `--collect` check their own plan against.
struct PlanFile {
    std::string config;            ///< configStamp
    std::vector<std::string> ids;  ///< the runs, in plan order
};
/// Writes `path` (the stamp, the IDs with their commands, the suite and the build's version).
void savePlanFile(const std::string& path, const PlanFile& plan, const std::string& suite_path,
                  const std::string& version, const std::vector<std::string>& commands);
/// Reads `path`; nullopt when it does not exist, std::runtime_error naming it when malformed.
std::optional<PlanFile> loadPlanFile(const std::string& path);

}  // namespace superloc::app
