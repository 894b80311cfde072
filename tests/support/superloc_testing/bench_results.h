// superloc-bench's results.md and results.json without what is measured, so that two outputs of
// one suite can be compared exactly (--jobs 1 against --jobs N, or against the same plan run by
// GNU parallel and gathered by --collect; doc/evaluation.md#runs-split-for-a-scheduler).
#pragma once

#include <nlohmann/json.hpp>

#include <sstream>
#include <string>

namespace superloc::testing {

/// results.md without: the preamble (the command and date; the note on shared cores of --jobs N
/// or on the machines of --collect), blank lines, the Runs table's wall time and peak memory
/// (its last two columns) and, with `measured_ms` (real runs; stand-ins write fixed times), the
/// "ms per frame" table.
inline std::string resultsMarkdownWithoutTimes(const std::string& md, bool measured_ms = false) {
    std::istringstream in(md);
    std::string out;
    bool in_runs = false, in_ms = false;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line.rfind("Produced by", 0) == 0 || line.find("(--jobs)") != std::string::npos ||
            line.rfind("Collected (--collect)", 0) == 0)
            continue;
        if (line.rfind("## ", 0) == 0) {
            in_runs = line == "## Runs";
            in_ms = measured_ms && line.rfind("## ms per frame", 0) == 0;
        }
        if (in_ms) continue;
        if (in_runs && (line.rfind("| ", 0) == 0 || line.rfind("|---", 0) == 0))
            for (int cut = 0; cut < 2; ++cut) line.erase(line.rfind('|', line.size() - 2) + 1);
        out += line + "\n";
    }
    return out;
}

/// results.json without the number of jobs, each run's wall time and peak memory and, with
/// `measured_ms`, its measured times per frame (metrics.timing and metrics.stages).
inline nlohmann::json resultsJsonWithoutTimes(const std::string& text, bool measured_ms = false) {
    auto j = nlohmann::json::parse(text);
    j.erase("jobs");
    for (auto& r : j["runs"]) {
        r.erase("wall_s"), r.erase("peak_rss_mb");
        if (measured_ms && r["metrics"].is_object()) r["metrics"].erase("timing"), r["metrics"].erase("stages");
    }
    return j;
}

}  // namespace superloc::testing
