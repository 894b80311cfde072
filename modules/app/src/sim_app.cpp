#include <CLI/CLI.hpp>
#include <superloc/core/config.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/tum.h>
#include <superloc/app/command_line.h>
#include <superloc/sim/noise.h>
#include <superloc/sim/raycaster.h>
#include <superloc/app/sim_app.h>
#include <superloc/sim/surface.h>
#include <superloc/sim/topview.h>
#include <superloc/sim/worlds.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace superloc::app {

SimApp::SimApp() : mrpt::system::COutputLogger("superloc-sim") {}

namespace {

struct SimFlags {
    std::string ini, out = "sim-out";
    std::vector<std::string> sets;
    std::string seed;
};

void defineCommandLine(CLI::App& cli, SimFlags& f, bool& dump_config) {
    cli.description(
        "Simulates a LiDAR + IMU + odom_alt sequence in a synthetic world (ini/sim/*.ini). Writes\n"
        "DIR/sequence.rawlog, gt_tum.txt, gt_map.ply, prior_map.pcd, topview.svg, config.ini.");
    cli.add_option("CONFIG.ini", f.ini, "the world and sensors (e.g. ini/sim/office.ini)")->required();
    cli.add_option("--out", f.out, "output folder")->type_name("DIR")->capture_default_str();
    cli.add_option("--seed", f.seed, "overrides [sim] seed")->type_name("N");
    addSetOption(cli, f.sets);
    cli.add_flag("--dump-config", dump_config, "print the effective configuration and exit");
}

}  // namespace

std::string SimApp::usage() {
    CLI::App cli("", "superloc-sim");
    SimFlags f;
    bool dump = false;
    defineCommandLine(cli, f, dump);
    return helpText(cli);
}

bool SimApp::initialize(int argc, const char* const* argv) {
    CLI::App cli("", "superloc-sim");
    SimFlags f;
    defineCommandLine(cli, f, dump_config_);
    if (!parseCommandLine(cli, argList(argc, argv))) return false;
    if (!f.seed.empty()) {
        if (f.seed.find_first_not_of("0123456789") != std::string::npos || f.seed.size() > 19)
            throw ConfigError("--seed '" + f.seed + "': expected a non-negative integer");
        f.sets.push_back("sim.seed=" + f.seed);
    }
    initialize(sim::loadSimConfig(f.ini, f.sets), f.out);
    return true;
}

void SimApp::initialize(sim::SimConfig cfg, const std::string& out_dir) {
    cfg_ = std::move(cfg);
    out_dir_ = out_dir;
}

namespace {

// The two small text outputs (io has no writer for SVG or INI text).
void writeText(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary);
    f << text;
    if (!f) throw std::runtime_error(path + ": cannot write");
}

}  // namespace

SimSummary SimApp::run() {
    using namespace sim;  // the world, the sensors and their models
    namespace fs = std::filesystem;
    const SimConfig& c = cfg_;
    const uint64_t seed = c.sim.seed;
    SimSummary sum;

    const SimScene scene = makeScene(c);
    const World& world = scene.world;
    const DensePath& path = scene.path;
    const SmoothTrajectory& traj = scene.trajectory;
    sum.mesh_triangles = world.mesh.size();
    const double t0 = traj.startTime(), t1 = traj.endTime();
    sum.duration = traj.duration();
    MRPT_LOG_INFO_STREAM("world " << world.name << ": " << world.mesh.size() << " triangles, route "
                                  << path.length() << " m, sequence " << sum.duration << " s");
    const RayCaster caster(world.mesh);

    std::error_code ec;
    fs::create_directories(out_dir_, ec);
    if (!fs::is_directory(out_dir_))
        throw std::runtime_error(out_dir_ + ": cannot create output folder");
    const auto out = [&](const char* name) { return (fs::path(out_dir_) / name).string(); };

    // Sequence: IMU, odom_alt, LiDAR sweeps and gt merged in time order (integer tick counters).
    io::RawlogWriter rawlog(out("sequence.rawlog"));
    ImuSimulator imu(c.imu, streamSeed(seed, "imu"));
    OdomAltSimulator odom(c.odom_alt, streamSeed(seed, "odom_alt"));
    std::mt19937_64 lidar_rng(streamSeed(seed, "lidar"));
    const SE3d T_imu_lidar = c.lidar.T_imu_lidar();
    const double period = c.lidar.period();
    const size_t n_imu =
        static_cast<size_t>(std::floor(traj.duration() * c.imu.rate_hz + 1e-9)) + 1;
    const size_t n_scan = static_cast<size_t>(std::floor(traj.duration() / period + 1e-9));
    const size_t n_odom =
        c.odom_alt.enabled
            ? static_cast<size_t>(std::floor(traj.duration() * c.odom_alt.rate_hz + 1e-9)) + 1
            : 0;
    Trajectory gt;
    size_t i_imu = 0, i_odom = 0, i_scan = 0;
    std::vector<Vec3d> positions;
    std::vector<Vec3f> normals;
    Vec3d last_pos = traj.pose(t0).translation();
    while (i_imu < n_imu || i_odom < n_odom || i_scan < n_scan) {
        const double t_imu = i_imu < n_imu ? t0 + i_imu / c.imu.rate_hz : 1e300;
        const double t_odom = i_odom < n_odom ? t0 + i_odom / c.odom_alt.rate_hz : 1e300;
        const double t_scan = i_scan < n_scan ? t0 + (i_scan + 1) * period : 1e300;
        if (t_imu <= t_odom && t_imu <= t_scan) {
            const BodyState s = traj.at(t_imu);
            rawlog.writeImu(imu.sample(s), c.imu.label);
            sum.max_speed = std::max(sum.max_speed, s.vel.norm());
            sum.max_yaw_rate = std::max(sum.max_yaw_rate, std::abs(s.omega_body.z()));
            sum.path_length += (s.T_map_body.translation() - last_pos).norm();
            last_pos = s.T_map_body.translation();
            if (i_imu % 20 == 0) positions.push_back(last_pos);
            ++i_imu;
        } else if (t_odom <= t_scan) {
            rawlog.writePose(odom.step(t_odom, traj.pose(t_odom)),
                             c.odom_alt.label);  // body (IMU) frame
            ++i_odom;
        } else if (i_scan % static_cast<size_t>(c.sim.scan_every) != 0) {
            ++i_scan;  // a revolution not written (scan_every)
        } else {
            const Scan scan =
                simulateSweep(caster, world.mesh, traj, c.lidar, t_scan, lidar_rng, &normals);
            for (const auto& n : normals) {
                int k;
                n.cwiseAbs().maxCoeff(&k);
                ++sum.normal_axis[k];
            }
            rawlog.writeScan(scan, c.lidar.label);
            PoseStamped g;
            g.t = t_scan;
            g.pose = traj.pose(t_scan) * T_imu_lidar;
            rawlog.writePose(g, "gt");
            gt.push_back(g);
            sum.points += scan.size();
            ++i_scan;
            if (on_progress) on_progress(0.9 * i_scan / std::max<size_t>(1, n_scan));
        }
    }
    rawlog.close();
    sum.scans = (n_scan + static_cast<size_t>(c.sim.scan_every) - 1) / static_cast<size_t>(c.sim.scan_every);
    sum.imu = n_imu;
    sum.odom_alt = n_odom;
    io::saveTum(out("gt_tum.txt"), gt);

    // Maps: survey sampling near the trajectory, and the prior map a user would be given.
    positions.push_back(traj.pose(t1).translation());
    {
        const NearMask near(positions, c.sim.gt_map_max_distance);
        PointCloud gt_map =
            sampleSurface(world.mesh, c.sim.gt_map_spacing, streamSeed(seed, "gt_map"),
                          [&](const Vec3f& p) { return near.contains(p); });
        gt_map.normals.clear();
        sum.gt_map_points = gt_map.size();
        io::savePointCloud(out("gt_map.ply"), gt_map);
    }
    if (on_progress) on_progress(0.95);
    {
        const NearMask near(positions, c.sim.prior_map_max_distance);
        const double spacing = std::min(0.05, c.sim.prior_map_voxel / 2);
        const PointCloud samples =
            sampleSurface(world.mesh, spacing, streamSeed(seed, "prior_samples"),
                          [&](const Vec3f& p) { return near.contains(p); });
        const PointCloud prior = makePriorMap(samples, c.sim.prior_map_voxel, c.sim.prior_map_noise,
                                              c.sim.prior_map_warp, streamSeed(seed, "prior_map"));
        sum.prior_map_points = prior.size();
        io::savePointCloud(out("prior_map.pcd"), prior);
    }

    // Documentation outputs: top view and the effective configuration.
    TopViewOptions tv;
    tv.title = world.name + " (seed " + std::to_string(seed) +
               "): " + std::to_string(static_cast<int>(std::round(sum.path_length))) + " m in " +
               std::to_string(static_cast<int>(std::round(sum.duration))) + " s, " +
               c.trajectory.platform;
    writeText(out("topview.svg"), topViewSvg(world.mesh, positions, tv));
    writeText(out("config.ini"), effectiveConfig(c));
    if (on_progress) on_progress(1.0);
    MRPT_LOG_INFO_FMT("travelled %.1f m in %.1f s, max %.2f m/s and %.1f deg/s yaw rate",
                      sum.path_length, sum.duration, sum.max_speed, sum.max_yaw_rate * 180 / M_PI);
    const double np = std::max<size_t>(1, sum.points);
    MRPT_LOG_INFO_FMT("returns on surfaces facing x / y / z (map frame): %.1f / %.1f / %.1f %%",
                      100 * sum.normal_axis[0] / np, 100 * sum.normal_axis[1] / np,
                      100 * sum.normal_axis[2] / np);
    MRPT_LOG_INFO_STREAM("wrote " << out_dir_ << ": " << sum.scans << " sweeps (" << sum.points
                                  << " points), " << sum.imu << " IMU, " << sum.odom_alt
                                  << " odom_alt, gt_map " << sum.gt_map_points
                                  << " points, prior_map " << sum.prior_map_points << " points");
    return sum;
}

}  // namespace superloc::app
