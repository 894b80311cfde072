#include <superloc/core/config.h>
#include <superloc/eval/frame_log.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace superloc::eval {
namespace {

std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> out;
    std::string cell;
    std::istringstream ss(line);
    while (std::getline(ss, cell, ',')) out.push_back(stripIniValue(cell));
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
}

}  // namespace

std::array<bool, 6> parseDegenerateAxes(const std::string& letters) {
    std::array<bool, 6> flags{};
    size_t pos = 0;
    while (pos < letters.size()) {
        bool matched = false;
        // Longest names first so "yaw" is not read as "y" + "aw".
        for (int k : {3, 4, 5, 0, 1, 2}) {
            const std::string name = kAxisNames[k];
            if (letters.compare(pos, name.size(), name) == 0) {
                flags[k] = true;
                pos += name.size();
                matched = true;
                break;
            }
        }
        if (!matched)
            throw std::invalid_argument("degenerate axes '" + letters + "': unknown axis letters");
    }
    return flags;
}

FrameLog loadFrameLog(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open frames CSV");
    std::string line;
    if (!std::getline(in, line))
        throw std::runtime_error(path + ":1: empty file, expected a header");
    const auto header = splitCsv(line);
    std::map<std::string, size_t> col;
    for (size_t k = 0; k < header.size(); ++k) col[header[k]] = k;
    for (const char* need : {"t", "ms_total"})
        if (!col.count(need))
            throw std::runtime_error(path + ":1: missing column '" + std::string(need) + "'");
    FrameLog log;
    log.has_gamma = true;
    for (int k = 0; k < 6; ++k)
        log.has_gamma &= col.count(std::string("gamma_") + kAxisNames[k]) > 0;

    log.has_health = col.count("health") > 0;
    static const char* kCov[9] = {"cov_xx", "cov_xy", "cov_xz", "cov_yy", "cov_yz", "cov_zz",
                                  "sigma_roll", "sigma_pitch", "sigma_yaw"};
    log.has_cov = true;
    for (const char* c : kCov) log.has_cov &= col.count(c) > 0;
    log.has_rules = true;
    for (const char* c : kRuleColumns) log.has_rules &= col.count(c) > 0;
    size_t lineno = 1;
    while (std::getline(in, line)) {
        ++lineno;
        if (stripIniValue(line).empty()) continue;
        const auto cells = splitCsv(line);
        const std::string where = path + ":" + std::to_string(lineno) + ": ";
        auto number = [&](const std::string& name) {
            const size_t k = col.at(name);
            double v;
            if (k >= cells.size() || !parseDouble(cells[k], v))
                throw std::runtime_error(where + "column '" + name + "' is not a number");
            return v;
        };
        FrameRecord f;
        f.t = number("t");
        f.ms_total = number("ms_total");
        if (log.has_gamma)
            for (int k = 0; k < 6; ++k) f.gamma[k] = number(std::string("gamma_") + kAxisNames[k]);
        const auto axes = [&](const std::string& name, std::array<bool, 6>& flags) {
            if (!col.count(name) || col[name] >= cells.size()) return;
            try {
                flags = parseDegenerateAxes(cells[col[name]]);
            } catch (const std::invalid_argument& e) {
                throw std::runtime_error(where + "column '" + name + "': " + e.what());
            }
        };
        axes("degenerate", f.degenerate);
        if (log.has_rules)
            for (int r = 0; r < kRules; ++r) axes(kRuleColumns[r], f.rule_flags[r]);
        if (log.has_health) {
            const size_t k = col["health"];
            f.health = k < cells.size() ? cells[k] : "";
            if (f.health != "ok" && f.health != "degraded" && f.health != "lost")
                throw std::runtime_error(where + "column 'health' is '" + f.health + "' (ok, degraded or lost)");
        }
        if (log.has_cov) {
            Mat3d P;
            P << number("cov_xx"), number("cov_xy"), number("cov_xz"), 0, number("cov_yy"), number("cov_yz"), 0, 0,
                number("cov_zz");
            P(1, 0) = P(0, 1), P(2, 0) = P(0, 2), P(2, 1) = P(1, 2);
            f.cov_pos = P;
            f.sigma_rot_deg = Vec3d(number("sigma_roll"), number("sigma_pitch"), number("sigma_yaw"));
        }
        // Per-stage times only from rows whose cell count matches the header (a free-text
        // column holding a comma would shift them); t, gamma and ms_total come first.
        for (const auto& [name, k] : col)
            if (name.rfind("ms_", 0) == 0 && (name == "ms_total" || cells.size() == header.size()))
                log.stage_ms[name].push_back(number(name));
        log.frames.push_back(f);
    }
    // The full covariances beside it (RunOutputs' trajectory_cov.txt), taken only when they are
    // the frames' own, line for line.
    const std::filesystem::path covp = std::filesystem::path(path).parent_path() / "trajectory_cov.txt";
    std::ifstream cin(covp);
    if (cin && !log.frames.empty()) {
        std::vector<Mat6d> covs;
        std::string l;
        size_t ln = 0;
        while (std::getline(cin, l)) {
            ++ln;
            if (l.empty() || l[0] == '#') continue;
            std::istringstream is(l);
            double t;
            Mat6d C;
            bool ok = static_cast<bool>(is >> t);
            for (int i = 0; i < 36 && ok; ++i) ok = static_cast<bool>(is >> C(i / 6, i % 6));
            if (!ok || covs.size() >= log.frames.size() || std::abs(t - log.frames[covs.size()].t) > 1e-6)
                throw std::runtime_error(covp.string() + ":" + std::to_string(ln) +
                                         ": not the covariance of frames.csv's frame (t and 36 numbers, same times)");
            covs.push_back(C);
        }
        if (covs.size() == log.frames.size()) {
            for (size_t i = 0; i < covs.size(); ++i) log.frames[i].cov6 = covs[i];
            log.has_cov6 = true;
        }
    }
    return log;
}

}  // namespace superloc::eval
