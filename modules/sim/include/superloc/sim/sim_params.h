// Section [sim]: which world, how long, which seed, and the map outputs.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <cstdint>
#include <string>

namespace superloc::sim {

struct SimParams : public mrpt::config::CLoadableOptions {
    std::string world = "office";      ///< corridor, cave, multifloor, openfield, office
    uint64_t seed = 1;                 ///< random parts of the world and all sensor noise
    double duration = 70.0;            ///< [s] sequence length (shorter if the route ends first)
    double start_time = 1700000000.0;  ///< [s] timestamp of the first sample (UNIX time)
    double gt_map_spacing = 0.02;  ///< [m] survey-map surface sampling (one point per spacing^2)
    double gt_map_max_distance =
        20.0;                       ///< [m] only surfaces this close to the trajectory are surveyed
    double prior_map_voxel = 0.1;   ///< [m] voxel size of prior_map.pcd
    double prior_map_noise = 0.01;  ///< [m] 1-sigma white mapping noise per point
    double prior_map_warp = 0.02;   ///< [m] amplitude of the smooth mapping warp (~10 m scale)
    double prior_map_max_distance = 40.0;  ///< [m] prior map extent around the trajectory
    int scan_every = 1;  ///< write one LiDAR revolution in N (a sparse sequence); IMU, odom_alt unaffected

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
};

}  // namespace superloc::sim
