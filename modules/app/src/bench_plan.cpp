#include <superloc/app/bench_plan.h>
#include <superloc/core/config.h>
#include <superloc/io/json_file.h>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace superloc::app {
namespace fs = std::filesystem;

std::vector<PlannedRun> planRuns(const SuiteSpec& suite) {
    std::vector<PlannedRun> plan;
    for (size_t i = 0; i < suite.sequences.size(); ++i)
        plan.push_back({plan.size(), "data:" + suite.sequences[i].name, i, std::nullopt});
    for (size_t i = 0; i < suite.sequences.size(); ++i)
        for (size_t k = 0; k < suite.methods.size(); ++k)
            plan.push_back({plan.size(), suite.sequences[i].name + "/" + suite.methods[k], i, k});
    return plan;
}

const PlannedRun& findRun(const std::vector<PlannedRun>& plan, const std::string& key) {
    for (const auto& r : plan)
        if (r.id == key) return r;
    long long index = -1;
    if (parseInteger(key, index) && index >= 0 && static_cast<size_t>(index) < plan.size())
        return plan[static_cast<size_t>(index)];
    const std::string range = plan.empty() ? "none" : "0-" + std::to_string(plan.size() - 1);
    throw std::invalid_argument("--run: '" + key +
                                "' is not a run of this plan (an ID data:SEQ or SEQ/METHOD, or an "
                                "index " + range + "; --plan lists them)");
}

std::string configStamp(const std::string& suite_text, const std::string& localize_config_text,
                        const std::vector<std::string>& localize_sets) {
    // FNV-1a 64 over the parts, each followed by a 0 byte so that parts cannot run together.
    std::uint64_t h = 14695981039346656037ull;
    const auto add = [&h](const std::string& s) {
        for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
        h = (h ^ 0u) * 1099511628211ull;
    };
    add(suite_text);
    add(localize_config_text);
    for (const auto& s : localize_sets) add(s);
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

void savePlanFile(const std::string& path, const PlanFile& plan, const std::string& suite_path,
                  const std::string& version, const std::vector<std::string>& commands) {
    io::Json runs = io::Json::array();
    for (size_t i = 0; i < plan.ids.size(); ++i)
        runs.push_back({{"index", i},
                        {"id", plan.ids[i]},
                        {"command", i < commands.size() ? commands[i] : std::string()}});
    io::saveJson(path, {{"config", plan.config},
                        {"suite", suite_path},
                        {"version", version},
                        {"runs", runs}});
}

std::optional<PlanFile> loadPlanFile(const std::string& path) {
    if (!fs::exists(path)) return std::nullopt;
    const io::Json j = io::loadJson(path);
    try {
        PlanFile p;
        p.config = j.at("config").get<std::string>();
        for (const auto& r : j.at("runs")) p.ids.push_back(r.at("id").get<std::string>());
        return p;
    } catch (const nlohmann::json::exception&) {
        throw std::runtime_error(path + ": not a plan of superloc-bench (no \"config\" or \"runs\")");
    }
}

}  // namespace superloc::app
