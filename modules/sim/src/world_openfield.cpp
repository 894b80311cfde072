// Openfield world: flat (slightly rough) ground and a handful of far objects. Only the ground
// (z, roll, pitch) is well constrained; x, y and yaw hang on a few distant returns.
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/sim/noise.h>
#include <superloc/sim/worlds.h>

#include <random>

namespace superloc::sim {

void OpenfieldParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                         const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(size, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ground_roughness, double, c, s);
    MRPT_LOAD_CONFIG_VAR(objects, int, c, s);
    MRPT_LOAD_CONFIG_VAR(object_min_dist, double, c, s);
    MRPT_LOAD_CONFIG_VAR(object_max_dist, double, c, s);
    MRPT_LOAD_CONFIG_VAR(loop_length, double, c, s);
    MRPT_LOAD_CONFIG_VAR(laps, int, c, s);
}

void OpenfieldParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                       const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(size, "[m] side of the ground square");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ground_roughness, "[m] ground relief amplitude");
    MRPT_SAVE_CONFIG_VAR_COMMENT(objects, "sparse objects (trees, poles, sheds)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(object_min_dist, "[m] from the route centre");
    MRPT_SAVE_CONFIG_VAR_COMMENT(object_max_dist, "[m] from the route centre");
    MRPT_SAVE_CONFIG_VAR_COMMENT(loop_length, "[m] rounded-rectangle route, length x 0.6 length");
    MRPT_SAVE_CONFIG_VAR_COMMENT(laps, "laps of the loop");
}

void OpenfieldParams::validate() const {
    const auto need = [](bool ok, const char* what) {
        if (!ok) throw ConfigError(std::string("[openfield] ") + what);
    };
    need(size >= 50 && size <= 2000, "size must be in [50, 2000] m");
    need(ground_roughness >= 0 && ground_roughness <= 0.5,
         "ground_roughness must be in [0, 0.5] m");
    need(objects >= 0 && objects <= 100, "objects must be in [0, 100]");
    need(object_min_dist > 0 && object_max_dist >= object_min_dist && object_max_dist < size / 2,
         "need 0 < object_min_dist <= object_max_dist < size/2");
    need(loop_length >= 5 && loop_length <= object_min_dist * 1.6,
         "loop_length must be in [5, 1.6 object_min_dist] m");
    need(laps >= 1 && laps <= 20, "laps must be in [1, 20]");
}

World buildOpenfield(const OpenfieldParams& p, uint64_t seed, double body_height) {
    World w;
    w.name = "openfield";
    Mesh& m = w.mesh;
    std::mt19937_64 rng(streamSeed(seed, "openfield"));
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const FractalNoise relief(streamSeed(seed, "openfield-ground"), 8.0, 2, 0.5);

    // Ground: 1 m grid near the route (fine relief), 4 m grid beyond.
    const auto groundZ = [&](double x, double y) { return p.ground_roughness * relief({x, y, 0}); };
    const auto gridPatch = [&](double x0, double y0, double x1, double y1, double cell) {
        const int nx = std::max(1, static_cast<int>(std::round((x1 - x0) / cell)));
        const int ny = std::max(1, static_cast<int>(std::round((y1 - y0) / cell)));
        const int base = static_cast<int>(m.vertices.size());
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i) {
                const double x = x0 + (x1 - x0) * i / nx, y = y0 + (y1 - y0) * j / ny;
                m.vertices.push_back(Vec3f(x, y, groundZ(x, y)));
            }
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const int a = base + j * (nx + 1) + i;
                m.triangles.emplace_back(a, a + 1, a + nx + 2);
                m.triangles.emplace_back(a, a + nx + 2, a + nx + 1);
                m.reflectivity.push_back(0.25f);
                m.reflectivity.push_back(0.25f);
            }
    };
    const double S = p.size / 2, inner = 32;
    gridPatch(-inner, -inner, inner, inner, 1.0);
    gridPatch(-S, -S, S, -inner, 4.0);
    gridPatch(-S, inner, S, S, 4.0);
    gridPatch(-S, -inner, -inner, inner, 4.0);
    gridPatch(inner, -inner, S, inner, 4.0);

    // Sparse objects: trees (trunk + crown box), poles, small sheds.
    for (int k = 0; k < p.objects; ++k) {
        const double a = 2 * M_PI * (k + 0.6 * U(rng)) / std::max(1, p.objects);
        const double r = p.object_min_dist + (p.object_max_dist - p.object_min_dist) * U(rng);
        const Vec3d c(r * std::cos(a), r * std::sin(a),
                      groundZ(r * std::cos(a), r * std::sin(a)) - 0.1);
        switch (k % 3) {
            case 0:
                m.addCylinder(c, 0.2, 3.0, 10, 0.4f);
                m.addOrientedBox(c + Vec3d(0, 0, 2.5), {3.0, 3.0, 3.0}, U(rng), 0.3f);
                break;
            case 1:
                m.addCylinder(c, 0.12, 6.0, 8, 0.6f);
                break;
            default:
                m.addOrientedBox(c, {4.0, 3.0, 2.8}, M_PI * U(rng), 0.7f);
                break;
        }
    }

    // Route: rounded rectangle laps centred on the origin.
    const double hx = p.loop_length / 2, hy = 0.3 * p.loop_length, z = body_height;
    w.route.push_back({{-hx, 0, z}, 1.0});
    for (int lap = 0; lap < p.laps; ++lap) {
        w.route.push_back({{-hx, -hy, z}, 1.0});
        w.route.push_back({{hx, -hy, z}, 1.0});
        w.route.push_back({{hx, hy, z}, 1.0});
        w.route.push_back({{-hx, hy, z}, 1.0});
        w.route.push_back({{-hx, lap + 1 == p.laps ? 0.0 : -0.5 * hy, z}, 1.0});
    }
    return w;
}

}  // namespace superloc::sim
