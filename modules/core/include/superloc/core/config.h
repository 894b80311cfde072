// Strict checking of INI sections against a Params struct (mrpt::config::CLoadableOptions).
//
// MRPT's readers silently turn "abc" into 0 and ignore misspelt keys; a localizer configured
// that way gives a silent wrong answer. Every module's Params is therefore validated against
// what its own saveToConfigFile() writes: the key must exist there, and the value must parse
// as the default's type (number, bool or free text).
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace mrpt::config {
class CConfigFileMemory;
}

namespace superloc {

/// Raised for a bad configuration; what() is one line naming the source, section and key.
class ConfigError : public std::runtime_error {
   public:
    using std::runtime_error::runtime_error;
};

/// Throws ConfigError if `section` of `cfg` holds a key that `defaults.saveToConfigFile` does
/// not write, or a value whose type differs from the default's (a number, a whole number when
/// the default is written as one, a boolean). `source` names the INI file (or "--set") in the
/// message. A missing section is fine (all defaults).
void validateSection(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const mrpt::config::CLoadableOptions& defaults, const std::string& source);

/// Loads `params` from `section` after validateSection(); the one call modules' users make.
template <class ParamsT>
ParamsT loadParams(
    const mrpt::config::CConfigFileBase& cfg, const std::string& section,
    const std::string& source) {
    ParamsT p;
    validateSection(cfg, section, p, source);
    p.loadFromConfigFile(cfg, section);
    p.validate();
    return p;
}

/// Value of an INI string with any trailing comment ("//", ";" or "#" after blanks) and
/// surrounding blanks removed.
std::string stripIniValue(const std::string& raw);

/// Parses a whole string as a finite double; false on any trailing garbage.
bool parseDouble(const std::string& s, double& out);
/// Parses a whole string as a whole number ("12", "-3"; not "2000.7", "1e3").
bool parseInteger(const std::string& s, long long& out);
/// Parses true/false/1/0/yes/no (case-insensitive).
bool parseBool(const std::string& s, bool& out);

/// Checks the lines of an INI text before MRPT parses it, which would take each of these
/// silently: a section header without its closing ']' (MRPT names a section after the header
/// and the lines below it), a key before any [section], a line that is not `key = value`, and a
/// key given twice in one section (MRPT keeps the last). Throws ConfigError
/// "<source>:<line>: ..." naming the section and key. Comments (`;`, `#`, `//`), blank lines and
/// MRPT's `@define` lines are skipped.
void checkIniText(const std::string& text, const std::string& source);

/// The INI sections an app reads, for checkSections().
struct IniSections {
    std::string app;                     ///< e.g. "superloc-localize", for the messages
    std::vector<std::string> reads;      ///< the sections the app reads: the only ones --set may name
    std::vector<std::string> shared;     ///< sections other apps read from the same file: ignored there
    std::vector<std::string> prefixes;   ///< section name prefixes the app reads (e.g. "seq.")
};

/// Throws ConfigError when an override of `sets` ("section.key=value") names a section that
/// `known.reads` does not hold, or when `cfg` has a section that is in neither `known.reads`
/// nor `known.shared` (a misspelling: MRPT would ignore it). The message names the --set, or
/// `ini_path`, the section's line and the section, and lists the sections the app reads.
/// Section names compare case-insensitively, as MRPT's do.
void checkSections(const mrpt::config::CConfigFileBase& cfg, const IniSections& known,
                   const std::string& ini_path, const std::vector<std::string>& sets);

/// cfg.setContent(text) after checkIniText(), with MRPT's parse errors (e.g. a malformed
/// `$eval{...}`, whose message spans several lines with a call trace) turned into a one-line
/// ConfigError naming `source`.
void setIniContent(mrpt::config::CConfigFileMemory& cfg, const std::string& text,
                   const std::string& source);

/// Reads the INI file `path` into `cfg` (setIniContent: MRPT's parse errors made one line).
/// A missing or unreadable file (or a folder) is ConfigError "<path>: cannot open <what>".
void loadIniFile(mrpt::config::CConfigFileMemory& cfg, const std::string& path,
                 const std::string& what = "the configuration file");

/// Applies "section.key=value" overrides (from --set) to a config, throwing ConfigError with
/// the offending text when it is not of that form.
void applyOverride(mrpt::config::CConfigFileBase& cfg, const std::string& assignment);

}  // namespace superloc
