// LocalizerParams: every section the Localizer reads, loaded and saved together (localizer_params.h).
#include <superloc/core/config.h>
#include <superloc/localization/localizer_params.h>

namespace superloc::localization {

LocalizerParams LocalizerParams::load(const mrpt::config::CConfigFileBase& cfg, const std::string& source) {
    LocalizerParams p;
    p.loc = loadParams<LocalizationParams>(cfg, "localization", source);
    p.assoc = loadParams<AssociationConfig>(cfg, "association", source);
    p.features = loadParams<features::FeaturesParams>(cfg, "features", source);
    p.fusion = loadParams<fusion::FusionParams>(cfg, "fusion", source);
    p.imu = loadParams<imu::ImuParams>(cfg, "imu", source);
    p.risk = loadParams<risk::RiskParams>(cfg, "risk", source);
    p.health = loadParams<HealthParams>(cfg, "health", source);
    p.relocalization = loadParams<RelocalizationParams>(cfg, "relocalization", source);
    p.global_search = loadParams<reloc::GlobalSearchParams>(cfg, "global_search", source);
    return p;
}

void LocalizerParams::save(mrpt::config::CConfigFileBase& cfg) const {
    loc.saveToConfigFile(cfg, "localization");
    assoc.saveToConfigFile(cfg, "association");
    features.saveToConfigFile(cfg, "features");
    fusion.saveToConfigFile(cfg, "fusion");
    imu.saveToConfigFile(cfg, "imu");
    risk.saveToConfigFile(cfg, "risk");
    health.saveToConfigFile(cfg, "health");
    relocalization.saveToConfigFile(cfg, "relocalization");
    global_search.saveToConfigFile(cfg, "global_search");
}

}  // namespace superloc::localization
