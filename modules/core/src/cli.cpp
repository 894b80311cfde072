#include <superloc/core/cli.h>
#include <superloc/core/config.h>

namespace superloc {

static std::string missing(const std::string& flag) {
    return flag + ": missing value (see --help)";
}

std::string flagValue(const std::vector<std::string>& args, size_t& i) {
    if (i + 1 >= args.size()) throw ConfigError(missing(args[i]));
    return args[++i];
}

std::string flagValue(int argc, const char* const* argv, int& i) {
    if (i + 1 >= argc) throw ConfigError(missing(argv[i]));
    return argv[++i];
}

}  // namespace superloc
