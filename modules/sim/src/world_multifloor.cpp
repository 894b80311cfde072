// Multifloor world: a switchback stairwell linking `floors` storeys, each with a short hallway.
// The shaft and hallways share plain vertical walls from bottom to top, so most returns
// constrain x, y and yaw; only treads, slabs and landings constrain z. A legged robot walks the
// ground-floor hallway, climbs every flight (landings: U-turns) and walks the top hallway.
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/sim/noise.h>
#include <superloc/sim/worlds.h>

#include <random>

namespace superloc::sim {

void MultifloorParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                          const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(floors, int, c, s);
    MRPT_LOAD_CONFIG_VAR(floor_height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(slab, double, c, s);
    MRPT_LOAD_CONFIG_VAR(steps_per_flight, int, c, s);
    MRPT_LOAD_CONFIG_VAR(step_run, double, c, s);
    MRPT_LOAD_CONFIG_VAR(flight_width, double, c, s);
    MRPT_LOAD_CONFIG_VAR(hallway_length, double, c, s);
    MRPT_LOAD_CONFIG_VAR(hallway_items, int, c, s);
}

void MultifloorParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                        const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(floors, "storeys linked by the stairwell");
    MRPT_SAVE_CONFIG_VAR_COMMENT(floor_height, "[m] storey height");
    MRPT_SAVE_CONFIG_VAR_COMMENT(slab, "[m] floor slab thickness");
    MRPT_SAVE_CONFIG_VAR_COMMENT(steps_per_flight, "two flights per storey");
    MRPT_SAVE_CONFIG_VAR_COMMENT(step_run, "[m] tread depth");
    MRPT_SAVE_CONFIG_VAR_COMMENT(flight_width, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(hallway_length, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(hallway_items, "cabinets / boxes per hallway");
}

void MultifloorParams::validate() const {
    const auto need = [](bool ok, const char* what) {
        if (!ok) throw ConfigError(std::string("[multifloor] ") + what);
    };
    need(floors >= 2 && floors <= 10, "floors must be in [2, 10]");
    need(floor_height >= 2.4 && floor_height <= 6, "floor_height must be in [2.4, 6] m");
    need(slab > 0.05 && slab < floor_height - 2.1, "slab must leave >= 2.1 m headroom");
    need(steps_per_flight >= 3 && steps_per_flight <= 30, "steps_per_flight must be in [3, 30]");
    need(step_run >= 0.2 && step_run <= 0.5, "step_run must be in [0.2, 0.5] m");
    need(flight_width >= 0.8 && flight_width <= 3, "flight_width must be in [0.8, 3] m");
    need(hallway_length >= 4 && hallway_length <= 100, "hallway_length must be in [4, 100] m");
    need(hallway_items >= 0 && hallway_items <= 20, "hallway_items must be in [0, 20]");
}

World buildMultifloor(const MultifloorParams& p, uint64_t seed, double body_height) {
    World w;
    w.name = "multifloor";
    Mesh& m = w.mesh;
    std::mt19937_64 rng(streamSeed(seed, "multifloor"));
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const double FH = p.floor_height, fw = p.flight_width, gap = 0.2, W = 2 * fw + gap;
    const double land = fw;                              // landing depth
    const double run = p.steps_per_flight * p.step_run;  // flight length
    const double x_end = land + run + land;              // shaft end wall
    const double HL = p.hallway_length, top = p.floors * FH;
    const double rise = FH / 2 / p.steps_per_flight;
    const float wall = 0.6f, conc = 0.4f;

    // Walls shared by shaft and hallways, full height; ground and roof.
    m.addGridQuad({-HL, 0, 0}, {HL + x_end, 0, 0}, {0, 0, top}, 8, p.floors, wall);
    m.addGridQuad({-HL, W, 0}, {HL + x_end, 0, 0}, {0, 0, top}, 8, p.floors, wall);
    m.addQuad({-HL, 0, 0}, {-HL, W, 0}, {-HL, W, top}, {-HL, 0, top}, wall);
    m.addQuad({x_end, 0, 0}, {x_end, W, 0}, {x_end, W, top}, {x_end, 0, top}, wall);
    m.addQuad({-HL, 0, 0}, {x_end, 0, 0}, {x_end, W, 0}, {-HL, W, 0}, conc);
    m.addQuad({-HL, 0, top}, {-HL, W, top}, {x_end, W, top}, {x_end, 0, top}, conc);

    for (int f = 0; f < p.floors; ++f) {
        const double z0 = f * FH;
        // Floor slab of storey f (hallway + floor landing); the ground floor is the ground quad.
        if (f > 0) m.addBox({-HL, 0, z0 - p.slab}, {land, W, z0}, conc);
        // Hallway items: cabinets against the walls.
        for (int k = 0; k < p.hallway_items; ++k) {
            const double x = -HL + 1 + (HL - 3) * U(rng);
            const bool left = U(rng) < 0.5;
            const Vec3d size(0.5 + 0.7 * U(rng), 0.45, 1.0 + 0.9 * U(rng));
            m.addOrientedBox({x, left ? W - 0.24 : 0.24, z0}, size, 0.0, 0.5f);
        }
        if (f + 1 == p.floors) break;
        // Mid landing and two flights up to the next storey.
        const double zm = z0 + FH / 2;
        m.addBox({land + run, 0, zm - 0.2}, {x_end, W, zm}, conc);
        for (int s = 0; s < p.steps_per_flight; ++s) {
            const double zt1 = z0 + (s + 1) * rise, zt2 = zm + (s + 1) * rise;
            const double xa = land + s * p.step_run;  // flight 1 goes +x on y in [0, fw]
            m.addBox({xa, 0, zt1 - rise - 0.15}, {xa + p.step_run, fw, zt1}, conc);
            const double xb = land + run - (s + 1) * p.step_run;  // flight 2 goes -x
            m.addBox({xb, fw + gap, zt2 - rise - 0.15}, {xb + p.step_run, W, zt2}, conc);
        }
    }

    // Route: ground hallway -> flights (U-turns on landings) -> top hallway.
    const double y1 = fw / 2, y2 = fw + gap + fw / 2, h = body_height, slow = 0.6;
    w.route.push_back({{-HL + 1.5, W / 2, h}, 1.0});
    for (int f = 0; f + 1 < p.floors; ++f) {
        const double z0 = f * FH, zm = z0 + FH / 2;
        w.route.push_back({{land - 0.1, y1, z0 + h}, slow});
        w.route.push_back({{land + run + 0.1, y1, zm + h}, slow});
        w.route.push_back({{land + run + land / 2, y1, zm + h}, slow});
        w.route.push_back({{land + run + land / 2, y2, zm + h}, slow});
        w.route.push_back({{land + run - 0.1, y2, zm + h}, slow});
        w.route.push_back({{land + 0.1, y2, z0 + FH + h}, slow});
        if (f + 2 < p.floors) {
            w.route.push_back({{land / 2, y2, z0 + FH + h}, slow});
            w.route.push_back({{land / 2, y1, z0 + FH + h}, slow});
        }
    }
    w.route.push_back({{-HL + 1.5, W / 2, top - FH + h}, 1.0});
    return w;
}

}  // namespace superloc::sim
