// Every section the Localizer reads ([localization] [association] [features] [fusion] [imu] [risk]
// [health] [relocalization] [global_search]), loaded and validated together.
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <superloc/features/features_params.h>
#include <superloc/fusion/fusion_params.h>
#include <superloc/localization/association_config.h>
#include <superloc/imu/imu_params.h>
#include <superloc/localization/health.h>
#include <superloc/localization/localization_params.h>
#include <superloc/localization/relocalization.h>
#include <superloc/reloc/global_search.h>
#include <superloc/risk/alignment_risk.h>

#include <string>

namespace superloc::localization {

/// Every section the Localizer reads, loaded and validated together.
struct LocalizerParams {
    LocalizationParams loc;
    AssociationConfig assoc;
    features::FeaturesParams features;
    fusion::FusionParams fusion;
    imu::ImuParams imu;
    risk::RiskParams risk;
    HealthParams health;
    RelocalizationParams relocalization;
    reloc::GlobalSearchParams global_search;

    /// Loads [localization] [association] [features] [fusion] [imu] [risk] [health] [relocalization] [global_search]; `source` names the file in errors.
    static LocalizerParams load(const mrpt::config::CConfigFileBase& cfg, const std::string& source);
    void save(mrpt::config::CConfigFileBase& cfg) const;
};

}  // namespace superloc::localization
