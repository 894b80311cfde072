// The five simulated worlds (doc/sim.md). Each is a triangle mesh plus the route its platform
// follows; each has its own INI section named after it ([corridor], [cave], ...).
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/sim/mesh.h>
#include <superloc/sim/path.h>

#include <cstdint>
#include <string>
#include <vector>

namespace mrpt::config {
class CConfigFileBase;
}

namespace superloc::sim {

/// A world: geometry and the route of the body (IMU) frame through it.
struct World {
    std::string name;
    Mesh mesh;
    std::vector<Waypoint> route;  ///< body positions (floor + body_height) and speed fractions
};

#define SUPERLOC_SIM_PARAMS_METHODS                                                               \
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)         \
        override;                                                                                 \
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override; \
    void validate() const;

/// [corridor]: a long featureless corridor opening onto a flat open area (paper's Corridor01/02).
struct CorridorParams : public mrpt::config::CLoadableOptions {
    double length = 100.0;       ///< [m] corridor length (>= 80)
    double width = 2.5;          ///< [m]
    double height = 2.8;         ///< [m]
    int recesses = 6;            ///< shallow door recesses, alternating sides
    double recess_depth = 0.15;  ///< [m]
    double recess_width = 1.0;   ///< [m]
    double open_size = 60.0;     ///< [m] side of the square open area beyond the corridor
    int open_features = 4;       ///< distant objects in the open area (poles, containers)
    double facade_height = 8.0;  ///< [m] building facade around the corridor mouth
    double weave = 0.25;         ///< [m] lateral weaving of the route in the corridor
    SUPERLOC_SIM_PARAMS_METHODS
};

/// [cave]: narrow, winding, sloping tunnel with rough self-similar walls (paper's Cave01-04).
struct CaveParams : public mrpt::config::CLoadableOptions {
    double length = 150.0;              ///< [m] centreline length
    double width_min = 2.0;             ///< [m]
    double width_max = 5.0;             ///< [m]
    double height = 2.8;                ///< [m] mean height (varies +-20 %)
    double max_slope_deg = 10.0;        ///< [deg]
    double winding_deg = 35.0;          ///< [deg] amplitude of heading changes
    double roughness = 0.15;            ///< [m] amplitude of wall relief
    double roughness_wavelength = 1.5;  ///< [m] largest relief wavelength (3 octaves)
    double station_step = 0.25;         ///< [m] mesh ring spacing along the centreline
    int ring_segments = 32;             ///< vertices per cross-section ring
    SUPERLOC_SIM_PARAMS_METHODS
};

/// [multifloor]: a switchback stairwell over three floors with short hallways (paper's Floor01).
struct MultifloorParams : public mrpt::config::CLoadableOptions {
    int floors = 3;
    double floor_height = 3.0;     ///< [m] storey height
    double slab = 0.3;             ///< [m] floor slab thickness
    int steps_per_flight = 9;      ///< two flights per storey, landing between
    double step_run = 0.28;        ///< [m] tread depth
    double flight_width = 1.2;     ///< [m]
    double hallway_length = 10.0;  ///< [m]
    int hallway_items = 2;         ///< cabinets / boxes per hallway
    SUPERLOC_SIM_PARAMS_METHODS
};

/// [openfield]: flat ground with sparse far objects.
struct OpenfieldParams : public mrpt::config::CLoadableOptions {
    double size = 200.0;             ///< [m] side of the ground square
    double ground_roughness = 0.02;  ///< [m] ground relief amplitude
    int objects = 6;                 ///< sparse objects (trees, poles, sheds)
    double object_min_dist = 25.0;   ///< [m] from the route's centre
    double object_max_dist = 70.0;   ///< [m]
    double loop_length = 40.0;       ///< [m] rounded-rectangle route, length x (0.6 length)
    int laps = 2;
    SUPERLOC_SIM_PARAMS_METHODS
};

/// [office]: rooms off a hallway, doors, furniture: well structured, the control case.
struct OfficeParams : public mrpt::config::CLoadableOptions {
    int rooms_per_side = 4;
    double room_width = 5.0;     ///< [m] along the hallway
    double room_depth = 6.0;     ///< [m]
    double hallway_width = 2.2;  ///< [m]
    double height = 2.7;         ///< [m]
    double door_width = 1.0;     ///< [m]
    int furniture_per_room = 4;  ///< desks and cabinets along the walls
    int rooms_visited = 4;       ///< rooms the route enters (alternating sides)
    SUPERLOC_SIM_PARAMS_METHODS
};

#undef SUPERLOC_SIM_PARAMS_METHODS

/// Names of the worlds buildWorld() knows.
const std::vector<std::string>& worldNames();

/// Builds world `name` from its INI section (validated; ConfigError naming `source` on a bad
/// key) with random parts drawn from `seed`; route heights use `body_height`.
World buildWorld(const std::string& name, const mrpt::config::CConfigFileBase& cfg,
                 const std::string& source, uint64_t seed, double body_height);

/// Checks a world section's keys and values (ConfigError naming `source`), without building.
void validateWorldSection(const std::string& name, const mrpt::config::CConfigFileBase& cfg,
                          const std::string& source);

World buildCorridor(const CorridorParams& p, uint64_t seed, double body_height);
World buildCave(const CaveParams& p, uint64_t seed, double body_height);
World buildMultifloor(const MultifloorParams& p, uint64_t seed, double body_height);
World buildOpenfield(const OpenfieldParams& p, uint64_t seed, double body_height);
World buildOffice(const OfficeParams& p, uint64_t seed, double body_height);

}  // namespace superloc::sim
