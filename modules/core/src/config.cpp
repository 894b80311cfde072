#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc/core/errors.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace superloc {

std::string stripIniValue(const std::string& raw) {
    std::string s = raw;
    for (const char* mark : {"//", ";", "#"}) {
        size_t pos = s.find(mark);
        while (pos != std::string::npos) {
            // A comment starts at the beginning or after a blank; "a;b" inside text stays.
            if (pos == 0 || std::isspace(static_cast<unsigned char>(s[pos - 1]))) {
                s.erase(pos);
                break;
            }
            pos = s.find(mark, pos + 1);
        }
    }
    const auto notspace = [](unsigned char c) { return !std::isspace(c); };
    s.erase(s.begin(), std::find_if(s.begin(), s.end(), notspace));
    s.erase(std::find_if(s.rbegin(), s.rend(), notspace).base(), s.end());
    return s;
}

bool parseDouble(const std::string& s, double& out) {
    if (s.empty()) return false;
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size() && std::isfinite(out);
}

bool parseBool(const std::string& s, bool& out) {
    std::string l = s;
    std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return std::tolower(c); });
    if (l == "true" || l == "1" || l == "yes" || l == "on") return out = true, true;
    if (l == "false" || l == "0" || l == "no" || l == "off") return out = false, true;
    return false;
}

void validateSection(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const mrpt::config::CLoadableOptions& defaults, const std::string& source) {
    if (!cfg.sectionExists(section)) return;
    mrpt::config::CConfigFileMemory ref;
    defaults.saveToConfigFile(ref, section);
    std::vector<std::string> known, given;
    ref.getAllKeys(section, known);
    cfg.getAllKeys(section, given);
    // MRPT pads keys written with comments ("voxel      = 0.5 // ..."): compare trimmed names.
    std::vector<std::string> known_raw = known;
    for (auto& k : known) k = stripIniValue(k);
    for (const auto& key : given) {
        const auto it = std::find(known.begin(), known.end(), stripIniValue(key));
        if (it == known.end()) {
            std::string list;
            for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
            throw ConfigError(
                source + ": unknown key '" + key + "' in section [" + section +
                "] (known keys: " + list + ")");
        }
        const std::string def = stripIniValue(ref.read_string(section, known_raw[it - known.begin()], ""));
        const std::string val = stripIniValue(cfg.read_string(section, key, ""));
        double d;
        bool b;
        if (parseBool(def, b) && !parseDouble(def, d)) {
            if (!parseBool(val, b))
                throw ConfigError(
                    source + ": [" + section + "] " + key + " = '" + val +
                    "' is not a boolean (use true or false)");
        } else if (parseDouble(def, d)) {
            if (!parseDouble(val, d))
                throw ConfigError(
                    source + ": [" + section + "] " + key + " = '" + val + "' is not a number");
        }
    }
}

void applyOverride(mrpt::config::CConfigFileBase& cfg, const std::string& assignment) {
    const size_t dot = assignment.find('.');
    const size_t eq = assignment.find('=');
    if (dot == std::string::npos || eq == std::string::npos || dot == 0 || dot + 1 >= eq)
        throw ConfigError(
            "--set '" + assignment + "': expected section.key=value, e.g. risk.degenerate_threshold=0.2");
    cfg.write(
        assignment.substr(0, dot), assignment.substr(dot + 1, eq - dot - 1),
        assignment.substr(eq + 1));
}

void loadIniFile(mrpt::config::CConfigFileMemory& cfg, const std::string& path, const std::string& what) {
    std::ifstream in(path);
    if (!std::filesystem::is_regular_file(path) || !in) throw ConfigError(path + ": cannot open " + what);
    std::stringstream text;
    text << in.rdbuf();
    setIniContent(cfg, text.str(), path);
}

void setIniContent(mrpt::config::CConfigFileMemory& cfg, const std::string& text,
                   const std::string& source) {
    try {
        cfg.setContent(text);
    } catch (const std::exception& e) {
        throw ConfigError(source + ": " + oneLineError(e));
    }
}

}  // namespace superloc
