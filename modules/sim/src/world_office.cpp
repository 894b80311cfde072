// Office world: a hallway with rooms on both sides, doors, and furniture along the room walls.
// Well structured in every direction: the control case. Walked handheld through a few rooms.
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/sim/noise.h>
#include <superloc/sim/worlds.h>

#include <random>

namespace superloc::sim {

void OfficeParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                      const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(rooms_per_side, int, c, s);
    MRPT_LOAD_CONFIG_VAR(room_width, double, c, s);
    MRPT_LOAD_CONFIG_VAR(room_depth, double, c, s);
    MRPT_LOAD_CONFIG_VAR(hallway_width, double, c, s);
    MRPT_LOAD_CONFIG_VAR(height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(door_width, double, c, s);
    MRPT_LOAD_CONFIG_VAR(furniture_per_room, int, c, s);
    MRPT_LOAD_CONFIG_VAR(rooms_visited, int, c, s);
}

void OfficeParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(rooms_per_side, "rooms on each side of the hallway");
    MRPT_SAVE_CONFIG_VAR_COMMENT(room_width, "[m] along the hallway");
    MRPT_SAVE_CONFIG_VAR_COMMENT(room_depth, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(hallway_width, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(height, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(door_width, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(furniture_per_room, "desks and cabinets along the walls");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rooms_visited, "rooms the route enters (alternating sides)");
}

void OfficeParams::validate() const {
    const auto need = [](bool ok, const char* what) {
        if (!ok) throw ConfigError(std::string("[office] ") + what);
    };
    need(rooms_per_side >= 1 && rooms_per_side <= 50, "rooms_per_side must be in [1, 50]");
    need(room_width >= 4 && room_width <= 20, "room_width must be in [4, 20] m");
    need(room_depth >= 5.5 && room_depth <= 20, "room_depth must be in [5.5, 20] m");
    need(hallway_width >= 1.8 && hallway_width <= 6, "hallway_width must be in [1.8, 6] m");
    need(height >= 2.3 && height <= 6, "height must be in [2.3, 6] m");
    need(door_width >= 0.8 && door_width < room_width - 1,
         "door_width must be in [0.8, room_width-1) m");
    need(furniture_per_room >= 0 && furniture_per_room <= 12,
         "furniture_per_room must be in [0, 12]");
    need(rooms_visited >= 0 && rooms_visited <= 2 * rooms_per_side,
         "rooms_visited must be in [0, 2 rooms_per_side]");
}

World buildOffice(const OfficeParams& p, uint64_t seed, double body_height) {
    World w;
    w.name = "office";
    Mesh& m = w.mesh;
    std::mt19937_64 rng(streamSeed(seed, "office"));
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const int N = p.rooms_per_side;
    const double RW = p.room_width, D = p.room_depth, hw = p.hallway_width / 2, H = p.height;
    const double X = N * RW, Y = hw + D, dw = p.door_width, door_h = std::min(2.1, H - 0.1);
    const float wall = 0.6f, floor_r = 0.3f;

    m.addGridQuad({0, -Y, 0}, {X, 0, 0}, {0, 2 * Y, 0}, N, 2, floor_r);
    m.addGridQuad({0, -Y, H}, {0, 2 * Y, 0}, {X, 0, 0}, 2, N, wall);
    const auto wallX = [&](double x, double y0, double y1) {  // wall in the plane x = const
        m.addQuad({x, y0, 0}, {x, y1, 0}, {x, y1, H}, {x, y0, H}, wall);
    };
    const auto wallY = [&](double y, double x0, double x1, double z0, double z1) {
        m.addQuad({x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}, wall);
    };
    wallX(0, -Y, Y);
    wallX(X, -Y, Y);
    wallY(-Y, 0, X, 0, H);
    wallY(Y, 0, X, 0, H);
    for (int i = 1; i < N; ++i) {
        wallX(i * RW, hw, Y);
        wallX(i * RW, -Y, -hw);
    }
    // Hallway walls with one door per room, doors at a random offset in each room.
    std::vector<double> door_x[2];
    for (int side = 0; side < 2; ++side) {
        const double y = side == 0 ? hw : -hw;
        double x = 0;
        for (int i = 0; i < N; ++i) {
            const double xc = i * RW + RW / 2 + (RW / 2 - dw / 2 - 1.6) * (2 * U(rng) - 1) * 0.5;
            door_x[side].push_back(xc);
            wallY(y, x, xc - dw / 2, 0, H);
            wallY(y, xc - dw / 2, xc + dw / 2, door_h, H);
            x = xc + dw / 2;
        }
        wallY(y, x, X, 0, H);
    }

    // Furniture in bands along the side and back walls of each room, clear of the route.
    for (int side = 0; side < 2; ++side) {
        const double sg = side == 0 ? 1 : -1;
        for (int i = 0; i < N; ++i) {
            const double x0 = i * RW;
            for (int k = 0; k < p.furniture_per_room; ++k) {
                const bool desk = U(rng) < 0.6;
                const Vec3d size = desk ? Vec3d(1.4 + 0.4 * U(rng), 0.75, 0.74)
                                        : Vec3d(0.9, 0.45, 1.2 + 0.8 * U(rng));
                const int where = static_cast<int>(3 * U(rng));  // 0: left wall, 1: right, 2: back
                Vec3d c;
                double yaw = 0;
                if (where == 2) {
                    c = Vec3d(x0 + 1 + (RW - 2) * U(rng), sg * (Y - size.y() / 2 - 0.02), 0);
                } else {
                    const double xw =
                        where == 0 ? x0 + size.y() / 2 + 0.02 : x0 + RW - size.y() / 2 - 0.02;
                    c = Vec3d(xw, sg * (hw + 1.6 + (D - 3.2) * U(rng)), 0);
                    yaw = M_PI / 2;
                }
                m.addOrientedBox(c, size, yaw, desk ? 0.45f : 0.55f);
            }
        }
    }

    // Route: along the hallway, into rooms (alternating sides): in, a diamond loop, out.
    const double z = body_height;
    w.route.push_back({{0.8, 0, z}, 1.0});
    for (int r = 0; r < p.rooms_visited; ++r) {
        const int side = r % 2, i = (r / 2) * 2 + side;  // rooms 0(+y),1(-y),2(+y),...
        if (i >= N) break;
        const double sg = side == 0 ? 1 : -1, xc = door_x[side][i];
        w.route.push_back({{xc, 0, z}, 1.0});
        w.route.push_back({{xc, sg * (hw + 1.6), z}, 0.7});
        w.route.push_back({{xc + 1.1, sg * (hw + 2.8), z}, 0.8});
        w.route.push_back({{xc, sg * (hw + 4.0), z}, 0.8});
        w.route.push_back({{xc - 1.1, sg * (hw + 2.8), z}, 0.8});
        w.route.push_back({{xc, sg * (hw + 1.6), z}, 0.7});
        w.route.push_back({{xc, 0.0, z}, 1.0});
    }
    w.route.push_back({{X - 1.0, 0, z}, 1.0});
    return w;
}

}  // namespace superloc::sim
