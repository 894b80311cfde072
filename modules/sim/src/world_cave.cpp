// Cave world: a narrow tunnel along a winding, sloping centreline; elliptic cross-sections of
// varying width and height, roughened by 3-octave value noise (self-similar: the same relief
// statistics everywhere), with a flatter rubble floor. Walked handheld from one end.
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/sim/noise.h>
#include <superloc/sim/worlds.h>

#include <cmath>
#include <random>

namespace superloc::sim {

void CaveParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(length, double, c, s);
    MRPT_LOAD_CONFIG_VAR(width_min, double, c, s);
    MRPT_LOAD_CONFIG_VAR(width_max, double, c, s);
    MRPT_LOAD_CONFIG_VAR(height, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_slope_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(winding_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(roughness, double, c, s);
    MRPT_LOAD_CONFIG_VAR(roughness_wavelength, double, c, s);
    MRPT_LOAD_CONFIG_VAR(station_step, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ring_segments, int, c, s);
}

void CaveParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(length, "[m] centreline length");
    MRPT_SAVE_CONFIG_VAR_COMMENT(width_min, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(width_max, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(height, "[m] mean height (varies +-20 %)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_slope_deg, "[deg]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(winding_deg, "[deg] amplitude of heading changes");
    MRPT_SAVE_CONFIG_VAR_COMMENT(roughness, "[m] amplitude of the wall relief");
    MRPT_SAVE_CONFIG_VAR_COMMENT(roughness_wavelength, "[m] largest relief wavelength");
    MRPT_SAVE_CONFIG_VAR_COMMENT(station_step, "[m] mesh ring spacing");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ring_segments, "vertices per cross-section ring");
}

void CaveParams::validate() const {
    const auto need = [](bool ok, const char* what) {
        if (!ok) throw ConfigError(std::string("[cave] ") + what);
    };
    need(length >= 20 && length <= 2000, "length must be in [20, 2000] m");
    need(width_min >= 1.2 && width_max >= width_min && width_max <= 20,
         "need 1.2 <= width_min <= width_max <= 20 m");
    need(height >= 2.0 && height <= 20, "height must be in [2, 20] m");
    need(max_slope_deg >= 0 && max_slope_deg <= 30, "max_slope_deg must be in [0, 30]");
    need(winding_deg >= 0 && winding_deg <= 90, "winding_deg must be in [0, 90]");
    need(roughness >= 0 && roughness < width_min / 4, "roughness must be in [0, width_min/4)");
    need(roughness_wavelength > 0.1, "roughness_wavelength must be > 0.1 m");
    need(station_step >= 0.05 && station_step <= 2, "station_step must be in [0.05, 2] m");
    need(ring_segments >= 8 && ring_segments <= 256, "ring_segments must be in [8, 256]");
}

World buildCave(const CaveParams& p, uint64_t seed, double body_height) {
    World w;
    w.name = "cave";
    std::mt19937_64 rng(streamSeed(seed, "cave"));
    std::uniform_real_distribution<double> U(0.0, 2 * M_PI);
    const double ph[6] = {U(rng), U(rng), U(rng), U(rng), U(rng), U(rng)};
    const double d2r = M_PI / 180;
    const FractalNoise relief(streamSeed(seed, "cave-relief"), p.roughness_wavelength, 3, 0.5);
    const FractalNoise rubble(streamSeed(seed, "cave-rubble"), 0.7, 2, 0.5);

    // Centreline (floor level): heading and slope as sums of incommensurate sinusoids.
    const int n = static_cast<int>(std::ceil(p.length / p.station_step)) + 1;
    std::vector<Vec3d> floor_pt(n);
    std::vector<double> heading(n), half_w(n), half_h(n);
    Vec3d pt(0, 0, 0);
    for (int i = 0; i < n; ++i) {
        const double s = i * p.station_step;
        heading[i] =
            p.winding_deg * d2r *
            (0.5 * std::sin(2 * M_PI * s / 47 + ph[0]) + 0.3 * std::sin(2 * M_PI * s / 19 + ph[1]) +
             0.9 * std::sin(2 * M_PI * s / 130 + ph[2] + ph[3]));
        const double slope = p.max_slope_deg * d2r *
                             (0.5 * std::sin(2 * M_PI * s / 61 + ph[2]) +
                              0.5 * std::sin(2 * M_PI * s / 173 + ph[5]));
        const double wf = 0.5 + 0.5 * (0.7 * std::sin(2 * M_PI * s / 29 + ph[3]) +
                                       0.3 * std::sin(2 * M_PI * s / 11 + ph[4]));
        half_w[i] = 0.5 * (p.width_min + (p.width_max - p.width_min) * wf);
        half_h[i] = 0.5 * p.height * (1 + 0.2 * std::sin(2 * M_PI * s / 37 + ph[5]));
        floor_pt[i] = pt;
        pt += p.station_step * Vec3d(std::cos(heading[i]) * std::cos(slope),
                                     std::sin(heading[i]) * std::cos(slope), std::sin(slope));
    }

    // Rings: an ellipse around the mid-height point, radially roughened, floor flattened.
    const int m = p.ring_segments;
    Mesh& mesh = w.mesh;
    for (int i = 0; i < n; ++i) {
        const Vec3d lateral(-std::sin(heading[i]), std::cos(heading[i]), 0);
        const Vec3d centre = floor_pt[i] + Vec3d(0, 0, half_h[i]);
        for (int k = 0; k < m; ++k) {
            const double a = 2 * M_PI * k / m;
            Vec3d q =
                centre + lateral * (half_w[i] * std::cos(a)) + Vec3d(0, 0, half_h[i] * std::sin(a));
            const Vec3d radial = (q - centre).normalized();
            q += radial * (p.roughness * relief(q));
            const double floor_z = floor_pt[i].z() + 0.3 * p.roughness * rubble(q);
            if (q.z() < floor_z + 0.15)
                q.z() = floor_z + 0.15 * (1 + std::sin(a)) * 0.5;  // flat-ish floor
            mesh.vertices.push_back(q.cast<float>());
        }
    }
    for (int i = 0; i + 1 < n; ++i)
        for (int k = 0; k < m; ++k) {
            const int a = i * m + k, b = i * m + (k + 1) % m, c = (i + 1) * m + (k + 1) % m,
                      d = (i + 1) * m + k;
            mesh.triangles.emplace_back(a, b, c);
            mesh.triangles.emplace_back(a, c, d);
            mesh.reflectivity.push_back(0.35f);
            mesh.reflectivity.push_back(0.35f);
        }
    // End caps (dead ends): fans to the ring centroids.
    for (int end = 0; end < 2; ++end) {
        const int i = end == 0 ? 0 : n - 1;
        Vec3d c = Vec3d::Zero();
        for (int k = 0; k < m; ++k) c += mesh.vertices[i * m + k].cast<double>();
        c /= m;
        const int ci = static_cast<int>(mesh.vertices.size());
        mesh.vertices.push_back(c.cast<float>());
        for (int k = 0; k < m; ++k) {
            mesh.triangles.emplace_back(ci, i * m + k, i * m + (k + 1) % m);
            mesh.reflectivity.push_back(0.35f);
        }
    }

    // Route: along the centreline at body height, from near one end to near the other.
    const int first = static_cast<int>(3.0 / p.station_step),
              stride = std::max(1, static_cast<int>(2.0 / p.station_step));
    for (int i = first; i < n - first; i += stride)
        w.route.push_back({floor_pt[i] + Vec3d(0, 0, body_height), 1.0});
    return w;
}

}  // namespace superloc::sim
