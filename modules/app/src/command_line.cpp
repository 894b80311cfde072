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
    // A value option given twice keeps the last one (a wrapper script may append an override);
    // --set collects every occurrence.
    for (CLI::Option* o : cli.get_options())
        if (o->get_multi_option_policy() == CLI::MultiOptionPolicy::Throw && o->get_name() != "--set")
            o->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
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
