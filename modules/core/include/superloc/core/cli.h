// Small helpers shared by the apps' command-line parsers.
#pragma once

#include <string>
#include <vector>

namespace superloc {

/// The value after the flag at args[i]; advances i past it. Throws ConfigError
/// "<flag>: missing value (see --help)" when the flag is the last argument.
std::string flagValue(const std::vector<std::string>& args, size_t& i);
/// The same on main()'s argc/argv.
std::string flagValue(int argc, const char* const* argv, int& i);

}  // namespace superloc
