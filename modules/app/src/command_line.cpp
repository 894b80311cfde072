#include <CLI/CLI.hpp>
#include <superloc/app/command_line.h>
#include <superloc/core/config.h>

#include <algorithm>

namespace superloc::app {

std::vector<std::string> argList(int argc, const char* const* argv) {
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
    return args;
}

bool parseCommandLine(CLI::App& cli, const std::vector<std::string>& args) {
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 pops from the back
    try {
        cli.parse(reversed);
    } catch (const CLI::CallForHelp&) {
        return false;
    } catch (const CLI::ParseError& e) {
        std::string msg = e.what();
        std::replace(msg.begin(), msg.end(), '\n', ' ');
        throw ConfigError(msg + " (see --help)");
    }
    return true;
}

std::string helpText(const CLI::App& cli) { return cli.help(); }

void addSetOption(CLI::App& cli, std::vector<std::string>& sets) {
    cli.add_option("--set", sets, "override one INI key, e.g. --set localization.method=icp (repeatable)")
        ->type_name("SECTION.KEY=VALUE")
        ->allow_extra_args(false);  // one override per --set
}

}  // namespace superloc::app
