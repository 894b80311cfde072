// Uses an installed SuperLoc: loads [localization] of the installed localize.ini preset and
// builds a small PriorMap (a voxelized 2 m x 2 m floor and wall), then prints what it got.
#include <mrpt/config/CConfigFile.h>
#include <superloc/core/config.h>
#include <superloc/localization/localization_params.h>
#include <superloc/map/prior_map.h>

#include <cstdio>
#include <exception>
#include <string>

int main(int argc, char** argv) {
    try {
        const std::string ini =
            argc > 1 ? argv[1] : std::string(SUPERLOC_CONSUMER_INI_DIR) + "/localize.ini";
        mrpt::config::CConfigFile cfg(ini);
        const auto params = superloc::loadParams<superloc::localization::LocalizationParams>(
            cfg, "localization", ini);

        superloc::PointCloud cloud;
        for (int i = 0; i < 40; ++i)
            for (int j = 0; j < 40; ++j) {
                cloud.points.emplace_back(0.05f * i, 0.05f * j, 0.0f);  // floor
                cloud.points.emplace_back(0.05f * i, 2.0f, 0.05f * j);  // wall
            }
        superloc::map::MapParams map_params;
        map_params.voxel_size = 0.1;
        const superloc::map::PriorMap map(cloud, map_params);

        std::printf("method=%s rounds=%d\n", superloc::localization::methodName(params.method), params.rounds);
        std::printf("PriorMap: %zu points from %zu\n", map.size(), cloud.points.size());
        return map.size() > 0 && map.size() < cloud.points.size() ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "superloc-consumer: %s\n", e.what());
        return 1;
    }
}
