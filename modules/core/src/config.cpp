#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc/core/errors.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
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

bool parseInteger(const std::string& s, long long& out) {
    if (s.empty()) return false;
    const size_t digits = (s[0] == '-' || s[0] == '+') ? 1 : 0;
    if (digits == s.size() || s.find_first_not_of("0123456789", digits) != std::string::npos)
        return false;
    errno = 0;
    out = std::strtoll(s.c_str(), nullptr, 10);
    return errno == 0;
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
        } else if (long long i; parseInteger(def, i)) {
            // MRPT writes integer keys as "12" and real ones as "12.000000" or "1.0e-09"; it
            // reads "2000.7" into an integer as 2000.
            if (!parseInteger(val, i))
                throw ConfigError(source + ": [" + section + "] " + key + " = '" + val +
                                  "' is not a whole number");
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

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

std::string trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t\r\v\f");
    if (a == std::string::npos) return "";
    return s.substr(a, s.find_last_not_of(" \t\r\v\f") + 1 - a);
}

bool isComment(const std::string& s) {
    return s.empty() || s[0] == ';' || s[0] == '#' || s.rfind("//", 0) == 0;
}

/// The section name of a header line "[name]" (with an optional comment after it); throws
/// ConfigError `where` + why when the line starts with '[' but is not such a header.
std::string sectionOf(const std::string& s, const std::string& where) {
    const size_t close = s.find(']');
    if (close == std::string::npos)
        throw ConfigError(where + "section header '" + s + "' has no closing ']'");
    const std::string name = trim(s.substr(1, close - 1));
    if (name.empty()) throw ConfigError(where + "section header '" + s + "' has no name");
    if (!isComment(trim(s.substr(close + 1))))
        throw ConfigError(where + "text after the section header '" + s + "'");
    return name;
}

/// Line (1-based) of the header of `section` in the file `path`; 0 when not found.
size_t sectionLine(const std::string& path, const std::string& section) {
    std::ifstream in(path);
    size_t n = 0;
    for (std::string line; std::getline(in, line);) {
        ++n;
        const std::string s = trim(line);
        if (s.empty() || s[0] != '[') continue;
        try {
            if (lower(sectionOf(s, "")) == lower(section)) return n;
        } catch (const ConfigError&) {
        }
    }
    return 0;
}

}  // namespace

void checkIniText(const std::string& text, const std::string& source) {
    std::istringstream in(text);
    std::string section;
    bool in_section = false;
    std::map<std::string, size_t> seen;  // "section\nkey" (lower case) -> line
    size_t n = 0;
    for (std::string line; std::getline(in, line);) {
        ++n;
        const std::string where = source + ":" + std::to_string(n) + ": ";
        const std::string s = trim(line);
        if (isComment(s) || s[0] == '@') continue;  // '@define NAME VALUE': MRPT's variables
        if (s[0] == '[') {
            section = sectionOf(s, where);
            in_section = true;
            continue;
        }
        const size_t eq = s.find('=');
        if (eq == std::string::npos)
            throw ConfigError(where + "'" + s.substr(0, 80) + "' is not key = value" +
                              (in_section ? " (in section [" + section + "])" : ""));
        const std::string key = trim(s.substr(0, eq));
        if (key.empty()) throw ConfigError(where + "'" + s + "' has no key before '='");
        if (!in_section)
            throw ConfigError(where + "key '" + key + "' before any [section]");
        const auto [it, fresh] = seen.try_emplace(lower(section) + "\n" + lower(key), n);
        if (!fresh)
            throw ConfigError(where + "[" + section + "] " + key + " is given twice (also on line " +
                              std::to_string(it->second) + "): keep one");
    }
}

void checkSections(const mrpt::config::CConfigFileBase& cfg, const IniSections& known,
                   const std::string& ini_path, const std::vector<std::string>& sets) {
    const auto in = [](const std::vector<std::string>& names, const std::string& s) {
        for (const auto& n : names)
            if (lower(n) == lower(s)) return true;
        return false;
    };
    const auto read = [&](const std::string& s) {
        for (const auto& p : known.prefixes)
            if (lower(s).rfind(lower(p), 0) == 0) return true;
        return in(known.reads, s);
    };
    std::string list;
    for (const auto& r : known.reads) list += (list.empty() ? "[" : ", [") + r + "]";
    for (const auto& p : known.prefixes) list += (list.empty() ? "[" : ", [") + p + "*]";
    for (const auto& a : sets) {
        const std::string section = a.substr(0, a.find('.'));
        if (!read(section))
            throw ConfigError("--set '" + a + "': " + known.app + " has no section [" + section +
                              "] (it reads " + list + ")");
    }
    std::vector<std::string> sections;
    cfg.getAllSections(sections);
    for (const auto& s : sections) {
        if (read(s) || in(known.shared, s)) continue;
        const size_t line = ini_path.empty() ? 0 : sectionLine(ini_path, s);
        throw ConfigError((ini_path.empty() ? std::string("--set") : ini_path) +
                          (line ? ":" + std::to_string(line) : std::string()) + ": unknown section [" +
                          s + "] (" + known.app + " reads " + list + ")");
    }
}

void setIniContent(mrpt::config::CConfigFileMemory& cfg, const std::string& text,
                   const std::string& source) {
    checkIniText(text, source);
    try {
        cfg.setContent(text);
    } catch (const std::exception& e) {
        throw ConfigError(source + ": " + oneLineError(e));
    }
}

}  // namespace superloc
