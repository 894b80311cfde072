// Corridor world: a long, smooth-walled corridor (x axis, along-axis degenerate for a LiDAR)
// with a few shallow door recesses, whose far end opens through a building facade onto a flat
// open area holding only a few distant objects. The car drives down the corridor, loops in the
// open area (U-turn at max yaw rate) and drives back in.
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/sim/noise.h>
#include <superloc/sim/worlds.h>

#include <algorithm>
#include <random>

namespace superloc::sim {

void CorridorParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                        const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(length, double, c, s);
    MRPT_LOAD_CONFIG_VAR(width, double, c, s);
    MRPT_LOAD_CONFIG_VAR(height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(recesses, int, c, s);
    MRPT_LOAD_CONFIG_VAR(recess_depth, double, c, s);
    MRPT_LOAD_CONFIG_VAR(recess_width, double, c, s);
    MRPT_LOAD_CONFIG_VAR(open_size, double, c, s);
    MRPT_LOAD_CONFIG_VAR(open_features, int, c, s);
    MRPT_LOAD_CONFIG_VAR(facade_height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(weave, double, c, s);
}

void CorridorParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                      const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(length, "[m] corridor length (>= 80)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(width, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(height, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(recesses, "shallow door recesses, alternating sides");
    MRPT_SAVE_CONFIG_VAR_COMMENT(recess_depth, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(recess_width, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(open_size, "[m] side of the open area beyond the corridor");
    MRPT_SAVE_CONFIG_VAR_COMMENT(open_features, "distant objects in the open area");
    MRPT_SAVE_CONFIG_VAR_COMMENT(facade_height, "[m] facade around the corridor mouth");
    MRPT_SAVE_CONFIG_VAR_COMMENT(weave, "[m] lateral weaving of the route in the corridor");
}

void CorridorParams::validate() const {
    const auto need = [](bool ok, const char* what) {
        if (!ok) throw ConfigError(std::string("[corridor] ") + what);
    };
    need(length >= 20 && length <= 1000, "length must be in [20, 1000] m");
    need(width >= 1.5 && width <= 10, "width must be in [1.5, 10] m");
    need(height >= 2 && height <= 10, "height must be in [2, 10] m");
    need(recesses >= 0 && recess_depth >= 0 && recess_width > 0, "recess values must be >= 0");
    need(recesses * (recess_width + 2) < length, "too many recesses for the corridor length");
    need(open_size >= 30 && open_size <= 1000, "open_size must be in [30, 1000] m");
    need(open_features >= 0 && open_features <= 50, "open_features must be in [0, 50]");
    need(facade_height >= height, "facade_height must be >= height");
    need(weave >= 0 && weave < width / 2 - 0.4, "weave must be in [0, width/2 - 0.4)");
}

World buildCorridor(const CorridorParams& p, uint64_t seed, double body_height) {
    World w;
    w.name = "corridor";
    Mesh& m = w.mesh;
    std::mt19937_64 rng(streamSeed(seed, "corridor"));
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const double L = p.length, hw = p.width / 2, H = p.height, d = p.recess_depth;
    const float wall = 0.6f, floor_r = 0.3f;

    // Floor and ceiling span the recesses too (hidden behind the walls elsewhere).
    m.addQuad({0, -hw - d, 0}, {L, -hw - d, 0}, {L, hw + d, 0}, {0, hw + d, 0}, floor_r);
    m.addQuad({0, -hw - d, H}, {0, hw + d, H}, {L, hw + d, H}, {L, -hw - d, H}, wall);
    m.addQuad({0, -hw, 0}, {0, hw, 0}, {0, hw, H}, {0, -hw, H}, wall);  // closed start

    // Recesses: evenly spread with jitter, alternating sides; door height 2.1 m.
    std::vector<std::pair<double, double>> rec[2];  // per side: [x0, x1]
    for (int k = 0; k < p.recesses; ++k) {
        const double slot = (L - 10) / std::max(1, p.recesses);
        const double x0 = 5 + slot * k + (slot - p.recess_width) * (0.2 + 0.6 * U(rng));
        rec[k % 2].push_back({x0, x0 + p.recess_width});
    }
    const double door_h = std::min(2.1, H - 0.1);
    for (int side = 0; side < 2; ++side) {
        const double sg = side == 0 ? 1.0 : -1.0, y = sg * hw, yb = sg * (hw + d);
        double x = 0;
        const auto wallQuad = [&](double xa, double xb, double za, double zb, double yy) {
            if (xb - xa < 1e-6 || zb - za < 1e-6) return;
            m.addQuad({xa, yy, za}, {xb, yy, za}, {xb, yy, zb}, {xa, yy, zb}, wall);
        };
        for (const auto& [x0, x1] : rec[side]) {
            wallQuad(x, x0, 0, H, y);
            wallQuad(x0, x1, door_h, H, y);   // lintel
            wallQuad(x0, x1, 0, door_h, yb);  // door (recess back)
            m.addQuad({x0, y, 0}, {x0, yb, 0}, {x0, yb, door_h}, {x0, y, door_h}, wall);  // jambs
            m.addQuad({x1, y, 0}, {x1, yb, 0}, {x1, yb, door_h}, {x1, y, door_h}, wall);
            m.addQuad({x0, y, door_h}, {x1, y, door_h}, {x1, yb, door_h}, {x0, yb, door_h}, wall);
            x = x1;
        }
        wallQuad(x, L, 0, H, y);
    }

    // Facade at x = L with the corridor mouth, and the open area's flat ground.
    const double S = p.open_size, FH = p.facade_height;
    m.addQuad({L, -S / 2, 0}, {L, -hw, 0}, {L, -hw, FH}, {L, -S / 2, FH}, wall);
    m.addQuad({L, hw, 0}, {L, S / 2, 0}, {L, S / 2, FH}, {L, hw, FH}, wall);
    m.addQuad({L, -hw, H}, {L, hw, H}, {L, hw, FH}, {L, -hw, FH}, wall);
    m.addGridQuad({L, -S / 2, 0}, {S, 0, 0}, {0, S, 0}, 6, 6, floor_r);

    // Route: down the corridor weaving gently, a loop in the open area, back in.
    const double z = body_height;
    w.route.push_back({{2, 0, z}, 1.0});
    for (double x = 12; x < L - 8; x += 12)
        w.route.push_back({{x, (static_cast<int>(x / 12) % 2 ? 1 : -1) * p.weave, z}, 1.0});
    w.route.push_back({{L - 2, 0, z}, 1.0});
    const double lx = std::min(30.0, S * 0.5), ly = std::min(16.0, S * 0.3);
    w.route.push_back({{L + 12, 0, z}, 1.0});
    w.route.push_back({{L + 12 + lx, 0, z}, 1.0});
    w.route.push_back({{L + 12 + lx, ly, z}, 1.0});
    w.route.push_back({{L + 6, ly, z}, 1.0});
    w.route.push_back({{L + 6, 0, z}, 0.8});
    w.route.push_back({{L - 2, 0, z}, 1.0});
    w.route.push_back({{4, 0, z}, 1.0});

    // A few distant features: poles and containers, kept off the loop.
    for (int k = 0; k < p.open_features; ++k) {
        Vec3d c;
        for (int tries = 0; tries < 100; ++tries) {
            c = Vec3d(L + 4 + (S - 8) * U(rng), -S / 2 + 4 + (S - 8) * U(rng), 0);
            const bool near_loop =
                c.x() > L + 1 && c.x() < L + 17 + lx && c.y() > -5 && c.y() < ly + 5;
            if (!near_loop) break;
        }
        if (k % 2 == 0)
            m.addCylinder(c, 0.15 + 0.2 * U(rng), 4 + 4 * U(rng), 12, 0.5f);
        else
            m.addOrientedBox(c, {6.0, 2.4, 2.6}, M_PI * U(rng), 0.7f);
    }
    return w;
}

}  // namespace superloc::sim
