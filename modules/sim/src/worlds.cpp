#include <superloc/core/config.h>
#include <superloc/sim/worlds.h>

namespace superloc::sim {

const std::vector<std::string>& worldNames() {
    static const std::vector<std::string> names = {"corridor", "cave", "multifloor", "openfield",
                                                   "office"};
    return names;
}

void validateWorldSection(const std::string& name, const mrpt::config::CConfigFileBase& cfg,
                          const std::string& source) {
    if (name == "corridor") loadParams<CorridorParams>(cfg, name, source);
    if (name == "cave") loadParams<CaveParams>(cfg, name, source);
    if (name == "multifloor") loadParams<MultifloorParams>(cfg, name, source);
    if (name == "openfield") loadParams<OpenfieldParams>(cfg, name, source);
    if (name == "office") loadParams<OfficeParams>(cfg, name, source);
}

World buildWorld(const std::string& name, const mrpt::config::CConfigFileBase& cfg,
                 const std::string& source, uint64_t seed, double body_height) {
    if (name == "corridor")
        return buildCorridor(loadParams<CorridorParams>(cfg, name, source), seed, body_height);
    if (name == "cave")
        return buildCave(loadParams<CaveParams>(cfg, name, source), seed, body_height);
    if (name == "multifloor")
        return buildMultifloor(loadParams<MultifloorParams>(cfg, name, source), seed, body_height);
    if (name == "openfield")
        return buildOpenfield(loadParams<OpenfieldParams>(cfg, name, source), seed, body_height);
    if (name == "office")
        return buildOffice(loadParams<OfficeParams>(cfg, name, source), seed, body_height);
    std::string list;
    for (const auto& n : worldNames()) list += (list.empty() ? "" : ", ") + n;
    throw ConfigError(source + ": [sim] world = '" + name + "' is unknown (known: " + list + ")");
}

}  // namespace superloc::sim
