#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/sim/lidar.h>

#include <cmath>

namespace superloc::sim {

SE3d LidarParams::T_imu_lidar() const {
    const double d2r = M_PI / 180;
    return makePoseRPY(ext_x, ext_y, ext_z, ext_roll_deg * d2r, ext_pitch_deg * d2r,
                       ext_yaw_deg * d2r);
}

void LidarParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(model, string, c, s);
    MRPT_LOAD_CONFIG_VAR(preset, string, c, s);
    MRPT_LOAD_CONFIG_VAR(label, string, c, s);
    MRPT_LOAD_CONFIG_VAR(beams, int, c, s);
    MRPT_LOAD_CONFIG_VAR(vfov_min_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(vfov_max_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(columns, int, c, s);
    MRPT_LOAD_CONFIG_VAR(rate_hz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(min_range, double, c, s);
    MRPT_LOAD_CONFIG_VAR(max_range, double, c, s);
    MRPT_LOAD_CONFIG_VAR(range_noise, double, c, s);
    MRPT_LOAD_CONFIG_VAR(dropout_rate, double, c, s);
    MRPT_LOAD_CONFIG_VAR(start_azimuth_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(rotation_sense, int, c, s);
    MRPT_LOAD_CONFIG_VAR(ext_x, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ext_y, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ext_z, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ext_roll_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ext_pitch_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ext_yaw_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(self_min_x, double, c, s);
    MRPT_LOAD_CONFIG_VAR(self_min_y, double, c, s);
    MRPT_LOAD_CONFIG_VAR(self_min_z, double, c, s);
    MRPT_LOAD_CONFIG_VAR(self_max_x, double, c, s);
    MRPT_LOAD_CONFIG_VAR(self_max_y, double, c, s);
    MRPT_LOAD_CONFIG_VAR(self_max_z, double, c, s);
}

void LidarParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(model, "free text (vlp16, os1-64, os0-128...)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(preset,
                                 "INI whose [lidar] is loaded first (path relative to this file)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(label, "sensor label of the observations");
    MRPT_SAVE_CONFIG_VAR_COMMENT(beams, "vertical channels");
    MRPT_SAVE_CONFIG_VAR_COMMENT(vfov_min_deg, "[deg] lowest beam elevation");
    MRPT_SAVE_CONFIG_VAR_COMMENT(vfov_max_deg, "[deg] highest beam elevation (evenly spaced)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(columns, "firings per revolution");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rate_hz, "[Hz] revolutions per second");
    MRPT_SAVE_CONFIG_VAR_COMMENT(min_range, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(max_range, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(range_noise, "[m] 1-sigma Gaussian range noise");
    MRPT_SAVE_CONFIG_VAR_COMMENT(dropout_rate, "[0..1] probability a return is lost");
    MRPT_SAVE_CONFIG_VAR_COMMENT(start_azimuth_deg, "[deg] azimuth of the first column");
    MRPT_SAVE_CONFIG_VAR_COMMENT(rotation_sense,
                                 "+1 counter-clockwise seen from above, -1 clockwise");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ext_x, "[m] LiDAR position in the IMU frame (T_imu_lidar)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ext_y, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ext_z, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ext_roll_deg, "[deg] LiDAR orientation in the IMU frame");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ext_pitch_deg, "[deg]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ext_yaw_deg, "[deg]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(self_min_x,
                                 "[m] platform body box in the LiDAR frame (self-occlusion)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(self_min_y, "[m] (disabled while any min >= max)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(self_min_z, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(self_max_x, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(self_max_y, "[m]");
    MRPT_SAVE_CONFIG_VAR_COMMENT(self_max_z, "[m]");
}

void LidarParams::validate() const {
    const auto need = [](bool ok, const char* what) {
        if (!ok) throw ConfigError(std::string("[lidar] ") + what);
    };
    need(beams >= 1 && beams <= 1024, "beams must be in [1, 1024]");
    need(columns >= 16 && columns <= 8192, "columns must be in [16, 8192]");
    need(vfov_max_deg >= vfov_min_deg && vfov_min_deg >= -90 && vfov_max_deg <= 90,
         "vfov_min_deg <= vfov_max_deg, both in [-90, 90]");
    need(rate_hz > 0 && rate_hz <= 100, "rate_hz must be in (0, 100]");
    need(min_range >= 0 && max_range > min_range, "need 0 <= min_range < max_range");
    need(range_noise >= 0, "range_noise must be >= 0");
    need(dropout_rate >= 0 && dropout_rate < 1, "dropout_rate must be in [0, 1)");
    need(rotation_sense == 1 || rotation_sense == -1, "rotation_sense must be 1 or -1");
}

namespace {

// Distance along unit ray d from the origin at which it enters box [lo, hi]; +inf if it misses.
double rayBoxEntry(const Vec3d& d, const Vec3d& lo, const Vec3d& hi) {
    double t0 = 0, t1 = 1e300;
    for (int k = 0; k < 3; ++k) {
        if (std::abs(d[k]) < 1e-12) {
            if (lo[k] > 0 || hi[k] < 0) return 1e300;
            continue;
        }
        double a = lo[k] / d[k], b = hi[k] / d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return 1e300;
    }
    return t0;
}

}  // namespace

Scan simulateSweep(const RayCaster& caster, const Mesh& mesh, const SmoothTrajectory& traj,
                   const LidarParams& p, double t_end, std::mt19937_64& rng,
                   std::vector<Vec3f>* normals_map) {
    if (normals_map) normals_map->clear();
    Scan scan;
    scan.t = t_end;
    scan.label = p.label;
    const SE3d T_imu_lidar = p.T_imu_lidar();
    scan.T_imu_lidar = T_imu_lidar;
    const double d2r = M_PI / 180, period = p.period();

    // Beam elevations, top beam first (firing order within a column).
    std::vector<double> elev(p.beams);
    for (int b = 0; b < p.beams; ++b)
        elev[b] = (p.beams == 1
                       ? p.vfov_max_deg
                       : p.vfov_max_deg - (p.vfov_max_deg - p.vfov_min_deg) * b / (p.beams - 1)) *
                  d2r;

    const Vec3d self_lo(p.self_min_x, p.self_min_y, p.self_min_z),
        self_hi(p.self_max_x, p.self_max_y, p.self_max_z);
    const bool self_box = (self_hi - self_lo).minCoeff() > 0;
    std::vector<double> self_entry(p.beams, 1e300);
    std::normal_distribution<double> noise(0.0, 1.0);
    std::uniform_real_distribution<double> unif(0.0, 1.0);
    std::vector<Vec3d> dirs_lidar(p.beams), dirs_map(p.beams);
    std::vector<RayHit> hits;
    scan.points.reserve(static_cast<size_t>(p.beams) * p.columns);
    for (int c = 0; c < p.columns; ++c) {
        const double rel = -period + period * c / p.columns;
        const SE3d T_map_lidar = traj.pose(t_end + rel) * T_imu_lidar;
        const double az = (p.start_azimuth_deg + p.rotation_sense * 360.0 * c / p.columns) * d2r;
        for (int b = 0; b < p.beams; ++b) {
            dirs_lidar[b] = Vec3d(std::cos(elev[b]) * std::cos(az),
                                  std::cos(elev[b]) * std::sin(az), std::sin(elev[b]));
            dirs_map[b] = T_map_lidar.linear() * dirs_lidar[b];
            if (self_box) self_entry[b] = rayBoxEntry(dirs_lidar[b], self_lo, self_hi);
        }
        caster.castFan(T_map_lidar.translation(), dirs_map, 0.0, p.max_range * 1.5, hits);
        for (int b = 0; b < p.beams; ++b) {
            // Draw both random numbers for every ray, so one ray's fate never shifts the others.
            const double n = noise(rng), drop = unif(rng);
            const RayHit& h = hits[b];
            if (!h.hit || self_entry[b] < h.range) continue;
            const double cos_inc = std::abs(h.normal.dot(dirs_map[b]));
            if (drop < p.dropout_rate || cos_inc < 0.02) continue;
            const double r = h.range + p.range_noise * n;
            if (r < p.min_range || r > p.max_range) continue;
            scan.points.push_back((dirs_lidar[b] * r).cast<float>());
            // Intensity: Lambertian return of the surface reflectivity, fading with range.
            const double refl = mesh.reflectivity[h.triangle];
            scan.intensity.push_back(
                static_cast<float>(refl * cos_inc / (1.0 + (r / 50.0) * (r / 50.0))));
            scan.rel_time.push_back(static_cast<float>(rel));
            if (normals_map) normals_map->push_back(h.normal.cast<float>());
        }
    }
    return scan;
}

}  // namespace superloc::sim
