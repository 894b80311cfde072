// Command lines of the apps, parsed by CLI11 (libcli11-dev, header-only, used in src/ only so
// that installed headers do not need it). Every app builds a CLI::App in its own .cpp and hands
// it here with the arguments; the options and their descriptions are the --help text.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace superloc::app {

/// argv[1..argc) as strings.
std::vector<std::string> argList(int argc, const char* const* argv);

/// Parses `args` (without the program name) with `cli`. Returns false when -h/--help was given
/// (print helpText(cli)). A bad command line (unknown option, missing value, a value of the wrong
/// type, a missing required argument) throws ConfigError with CLI11's one-line reason and
/// "(see --help)". An option given twice keeps its last value; --set keeps them all.
bool parseCommandLine(CLI::App& cli, const std::vector<std::string>& args);

/// The --help text: usage line, options with their descriptions, description and footer.
std::string helpText(const CLI::App& cli);

/// Adds the repeatable `--set section.key=value` INI override every INI-driven app takes.
void addSetOption(CLI::App& cli, std::vector<std::string>& sets);

}  // namespace superloc::app
