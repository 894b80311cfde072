#include <CLI/CLI.hpp>
#include <mrpt/config/CConfigFileBase.h>
#include <superloc/fusion/pose_posterior.h>
#include <superloc/app/command_line.h>
#include <superloc/core/config.h>
#include <superloc/core/errors.h>
#include <superloc/core/se3.h>
#include <superloc/eval/timing.h>
#include <superloc/eval/trajectory_metrics.h>
#include <superloc/io/map_tiles.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>
#include <superloc/localization/localization_params.h>
#include <superloc/localization/map_tile_follower.h>
#include <superloc/app/ini_sections.h>
#include <superloc/app/localize_app.h>

#include <superloc/app/observability_scan.h>

#include <chrono>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace superloc::app {

namespace fs = std::filesystem;

void RunParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    rawlog = c.read_string(s, "rawlog", rawlog);
    map = c.read_string(s, "map", map);
    out = c.read_string(s, "out", out);
    initial_pose = c.read_string(s, "initial_pose", initial_pose);
    initial_pose_tum = c.read_string(s, "initial_pose_tum", initial_pose_tum);
    MRPT_LOAD_CONFIG_VAR(localized_map_voxel, double, c, s);
    MRPT_LOAD_CONFIG_VAR(save_localized_map, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(save_report, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(save_observability_scan, bool, c, s);
}

void RunParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(rawlog, "input rawlog (--rawlog)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(map, "prior map file .pcd/.ply/... (--map)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(out, "output folder (--out)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(initial_pose, "x y z qx qy qz qw of the LiDAR in the map, or auto (global search)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(initial_pose_tum, "TUM file: its pose at the first scan's time is the initial pose");
    MRPT_SAVE_CONFIG_VAR_COMMENT(localized_map_voxel, "[m] voxel of localized_map.pcd");
    MRPT_SAVE_CONFIG_VAR_COMMENT(save_localized_map, "write localized_map.pcd");
    MRPT_SAVE_CONFIG_VAR_COMMENT(save_report, "write report.html (the run at a glance) at the end");
    MRPT_SAVE_CONFIG_VAR_COMMENT(save_observability_scan, "write observability_scan.ply (grows with the area covered)");
}

void RunParams::validate() const {
    if (localized_map_voxel < 0) throw ConfigError("[run] localized_map_voxel must be >= 0");
    if (!initial_pose.empty() && !initial_pose_tum.empty())
        throw ConfigError("[run] give initial_pose or initial_pose_tum, not both");
    if (!initial_pose.empty() && initial_pose != "auto") parsePoseString(initial_pose, "[run] initial_pose");
}

SE3d parsePoseString(const std::string& s, const std::string& what) {
    std::istringstream is(s);
    double v[7];
    for (double& x : v) {
        std::string tok;
        if (!(is >> tok) || !parseDouble(tok, x))
            throw ConfigError(what + " = '" + s + "': expected 7 numbers \"x y z qx qy qz qw\"");
    }
    std::string extra;
    if (is >> extra) throw ConfigError(what + " = '" + s + "': expected 7 numbers \"x y z qx qy qz qw\"");
    if (std::abs(std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]) - 1.0) > 0.01)
        throw ConfigError(what + " = '" + s + "': the quaternion is not unit");
    return makePose(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
}

LocalizeApp::LocalizeApp() : mrpt::system::COutputLogger("superloc-localize") {}

namespace {

/// The command line of superloc-localize; every value lands in `a`.
struct LocalizeArgs {
    std::string config, rawlog, map, method, out, pose, pose_tum;
    std::vector<std::string> sets;
    bool dump = false, quiet = false;
};

void defineCommandLine(CLI::App& cli, LocalizeArgs& a) {
    cli.description(
        "Localizes every LiDAR scan of the rawlog in the prior map and writes DIR/trajectory.tum,\n"
        "DIR/frames.csv, DIR/summary.json, DIR/localized_map.pcd, DIR/observability_scan.ply,\n"
        "DIR/report.html.\n"
        "Flags override the INI keys of [run] and [localization] method.");
    cli.add_option("CONFIG.ini", a.config, "the configuration (e.g. ini/localize.ini)")->required();
    cli.add_option("--rawlog", a.rawlog, "input rawlog ([run] rawlog)");
    cli.add_option("--map", a.map, "prior map .pcd/.ply/.bin/.txt/.pointsmap, or a tile directory of superloc-map --tile-size ([run] map)");
    cli.add_option("--method", a.method,
                   "icp, ndt, superloc (odom_alt prior weighted by the alignment risk), passive\n"
                   "(odom_alt prior, fixed weight), eigen_remap (Zhang et al. 2016)");
    cli.add_option("--out", a.out, "output folder ([run] out)");
    cli.add_option("--initial-pose", a.pose,
                   "\"x y z qx qy qz qw\" of the LiDAR in the map, or auto (global localization)");
    cli.add_option("--initial-pose-tum", a.pose_tum, "TUM file: its pose at the first scan's time")
        ->excludes("--initial-pose");
    app::addSetOption(cli, a.sets);
    cli.add_flag("--dump-config", a.dump, "print the effective configuration (every section) and exit");
    cli.add_flag("--quiet", a.quiet, "errors only");
}

}  // namespace

std::string LocalizeApp::usage() {
    CLI::App cli("", "superloc-localize");
    LocalizeArgs a;
    defineCommandLine(cli, a);
    return helpText(cli);
}

LocalizeApp::Action LocalizeApp::initialize(int argc, const char* const* argv) {
    return initialize(argList(argc, argv));
}

LocalizeApp::Action LocalizeApp::initialize(const std::vector<std::string>& args) {
    CLI::App cli("", "superloc-localize");
    LocalizeArgs a;
    defineCommandLine(cli, a);
    if (!parseCommandLine(cli, args)) return Action::Help;
    config_path_ = a.config;
    quiet_ = a.quiet;
    const std::string &rawlog = a.rawlog, &map = a.map, &method = a.method, &out = a.out, &pose = a.pose,
                      &pose_tum = a.pose_tum;
    const std::vector<std::string>& sets = a.sets;
    const bool dump = a.dump;
    loadIniFile(cfg_, config_path_);
    for (const auto& s : sets) applyOverride(cfg_, s);
    checkSections(cfg_, localizeSections(), config_path_, sets);
    if (cli.count("--method") > 0) {
        // Given, even empty ('--method ""' from a script's unset variable): checked, not skipped.
        try {
            localization::methodFromString(method);
        } catch (const ConfigError& e) {
            throw ConfigError(std::string("--method: ") + e.what());
        }
        cfg_.write("localization", "method", method);
    }
    if (quiet_) setMinLoggingLevel(mrpt::system::LVL_ERROR);

    const std::string src = config_path_ + (sets.empty() ? "" : " (+ --set)");
    run_ = loadParams<RunParams>(cfg_, "run", src);
    // INI paths are relative to the INI's folder; flags to the working directory.
    const fs::path ini_dir = fs::path(config_path_).parent_path();
    const auto rel = [&](std::string& p, const char* key) {
        const bool from_ini = !stripIniValue(cfg_.read_string("run", key, "")).empty();
        if (from_ini && !p.empty() && fs::path(p).is_relative())
            p = (ini_dir / p).lexically_normal().string();
    };
    rel(run_.rawlog, "rawlog");
    rel(run_.map, "map");
    rel(run_.out, "out");
    rel(run_.initial_pose_tum, "initial_pose_tum");
    if (!rawlog.empty()) run_.rawlog = rawlog;
    if (!map.empty()) run_.map = map;
    if (!out.empty()) run_.out = out;
    if (!pose.empty() && pose != "auto") parsePoseString(pose, "--initial-pose");  // named as given
    if (!pose.empty()) run_.initial_pose = pose, run_.initial_pose_tum.clear();
    if (!pose_tum.empty()) run_.initial_pose_tum = pose_tum, run_.initial_pose.clear();
    run_.validate();
    loc_ = localization::LocalizerParams::load(cfg_, src);
    rawlog_ = loadParams<io::RawlogParams>(cfg_, "rawlog", src);
    map_ = loadParams<map::MapParams>(cfg_, "map", src);
    if (dump) return Action::DumpConfig;
    if (run_.rawlog.empty()) throw ConfigError("no rawlog: give --rawlog F or [run] rawlog");
    if (run_.map.empty()) throw ConfigError("no map: give --map F or [run] map");
    if (!fs::exists(run_.rawlog)) throw ConfigError(run_.rawlog + ": rawlog not found");
    if (!fs::exists(run_.map)) throw ConfigError(run_.map + ": map file not found");
    return Action::Run;
}

std::string LocalizeApp::dumpConfig() const {
    mrpt::config::CConfigFileMemory c;
    run_.saveToConfigFile(c, "run");
    loc_.save(c);
    rawlog_.saveToConfigFile(c, "rawlog");
    map_.saveToConfigFile(c, "map");
    return c.getContent();
}

int LocalizeApp::run(const std::function<void(const localization::FrameReport&)>& on_frame) {
    // Initial pose (T_map_lidar).
    std::optional<SE3d> T0;
    Trajectory T0_tum;  // --initial-pose-tum: interpolated at the first scan's time
    const bool auto_pose = run_.initial_pose == "auto";
    if (!run_.initial_pose.empty() && !auto_pose) T0 = parsePoseString(run_.initial_pose, "--initial-pose");
    if (!run_.initial_pose_tum.empty()) {
        T0_tum = io::loadTum(run_.initial_pose_tum);
        if (T0_tum.empty()) throw ConfigError(run_.initial_pose_tum + ": no pose in the TUM file");
    }
    if (!T0 && T0_tum.empty() && !auto_pose)
        MRPT_LOG_WARN("no initial pose given: the first scan starts at the map origin (--initial-pose auto searches "
                      "the whole map)");

    // A tiled map (a directory with tiles.csv) is loaded around the initial pose, then follows
    // the robot (localization::MapTileFollower, doc/map.md "Tiled maps").
    std::optional<localization::MapTileFollower> tiles;
    if (io::isMapTileDir(run_.map)) {
        if (auto_pose)
            throw ConfigError("--initial-pose auto searches a whole map; the tiled map " + run_.map +
                              " is loaded around a given pose: give --initial-pose or --initial-pose-tum");
        tiles.emplace(run_.map, map_, loc_);
    }
    const auto t_map = std::chrono::steady_clock::now();
    std::shared_ptr<const map::PriorMap> prior;
    if (tiles) {
        Vec3d c = Vec3d::Zero();  // the initial pose's position (a TUM file's first pose)
        if (T0)
            c = T0->translation();
        else if (!T0_tum.empty())
            c = T0_tum.front().pose.translation();
        prior = tiles->start(c);
        MRPT_LOG_INFO_FMT("map %s: %zu of %zu tiles (%zu points) within %.0f m of (%.1f, %.1f)", run_.map.c_str(),
                          tiles->tiles().tilesLoaded(), tiles->tiles().index().tiles.size(),
                          tiles->tiles().pointsLoaded(), tiles->tiles().radius(), c.x(), c.y());
    } else {
        prior = std::make_shared<map::PriorMap>(map::PriorMap::load(run_.map, map_));
    }
    MRPT_LOG_INFO_FMT("map %s: %zu points, prepared in %.2f s", run_.map.c_str(), prior->size(),
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_map).count());
    if (prior->size() == 0)
        throw ConfigError(run_.map + (tiles ? ": no map tile within [map] tile_radius of the initial pose"
                                            : ": the map has no points"));
    // Destroyed with the map before the last outputs are written (finish): what they build then
    // does not add to the run's peak memory.
    std::optional<localization::Localizer> loc_holder;
    localization::Localizer& loc = loc_holder.emplace(loc_, prior);
    loc.setMinLoggingLevel(getMinLoggingLevel());
    if (loc.globalSearch())
        MRPT_LOG_INFO_FMT("global search grids: %.2f s, %.1f MB", loc.globalSearch()->buildSeconds(),
                          static_cast<double>(loc.globalSearch()->memoryBytes()) / 1e6);
    if (auto_pose) {
        if (!loc.globalSearch())
            throw ConfigError("--initial-pose auto needs [relocalization] enabled = true");
        loc.relocalize();
    }
    // The initial pose (localization::StartPose): checked against the map's bounds, a TUM file's
    // pose taken at the first scan's time.
    if (T0) loc.setInitialPose(*T0, "--initial-pose");
    if (!T0_tum.empty()) loc.setInitialPose(T0_tum, run_.initial_pose_tum);
    io::RawlogReader reader(run_.rawlog, rawlog_);
    reader.logger().setMinLoggingLevel(getMinLoggingLevel());  // --quiet: errors only
    RunOutputs out(run_.out, run_.save_localized_map ? run_.localized_map_voxel : -1.0, run_.save_report);
    if (RunReport* report = out.report()) {
        report->setInputs({{"configuration", config_path_}, {"rawlog", run_.rawlog}, {"map", run_.map}});
        report->addMapPoints(prior->points());
    }
    const bool body = loc_.loc.output_frame == "body";
    // Observability scan: correspondence points coloured by translation label.
    ObservabilityScan obs_scan(std::max(0.05, run_.localized_map_voxel));
    const std::string obs_path = (fs::path(run_.out) / "observability_scan.ply").string();
    // What the outputs need of each frame, computed by the Localizer after the frame's time.
    localization::FrameOutputs frame_out;
    frame_out.map_voxel = run_.save_localized_map ? std::max(0.05, run_.localized_map_voxel) : 0.0;
    frame_out.observability = run_.save_observability_scan;

    summary_ = RunSummary{};
    summary_.method = localization::methodName(loc_.loc.method);
    summary_.map_points = prior->size();
    summary_.map_prepare_s = prior->prepareSeconds();
    summary_.map_points_max = prior->size();
    RunTally tally;
    io::RawlogItem item;
    bool in_divergence = false;
    // The statistics of the frames processed so far, and summary.json, localized_map.pcd and
    // observability_scan.ply from them: at the end of the rawlog, and also when the run stops on
    // an error (doc/localizer.md "Faults"), so that every output says what was done.
    const auto finish = [&](const std::string& error) {
        // Nothing below needs the localizer or the map (a tiled map's follower stays: its
        // statistics and tile index are read).
        loc_holder.reset();
        prior.reset();
        summary_.rawlog = reader.stats();
        if (tiles) {
            const auto& ts = tiles->stats();
            summary_.map_reloads = ts.reloads;
            summary_.map_points_max = ts.points_max;
            summary_.map_reload_s_max = ts.load_s_max;
            summary_.map_reload_wait_s_max = ts.wait_s_max;
        }
        summary_.status = error.empty() ? "ok" : "failed";
        summary_.error = error;
        tally.fill(summary_);
        // A tiled map: the report's map is every tile the run came near, not only the first ones.
        if (RunReport* report = out.report(); report && tiles)
            for (const auto& file : tilesAlong(tiles->tiles().index(), report->frames(), tiles->tiles().radius())) {
                try {
                    report->addMapPoints(io::loadPointCloud(file).points);
                } catch (const std::exception& e) {
                    MRPT_LOG_WARN_FMT("report.html: map tile left out: %s", oneLineError(e).c_str());
                }
            }
        out.finish(summary_);
        if (run_.save_observability_scan) obs_scan.write(obs_path);
    };
    try {
        while (reader.next(item)) {
            switch (item.kind) {
                case io::RawlogItem::Kind::Imu: loc.addImu(item.imu()); break;
                case io::RawlogItem::Kind::OdomAlt: loc.addOdomAlt(item.pose()); break;
                case io::RawlogItem::Kind::GroundTruth: tally.addGroundTruth(item.pose()); break;
                case io::RawlogItem::Kind::Lidar: {
                    const localization::FrameReport r = loc.process(item.scan(), &frame_out);
                    const SE3d T = body ? r.T_map_imu : r.T_map_lidar;
                    if (tiles && r.health != localization::Health::Lost &&
                        tiles->update(r.T_map_lidar.translation(), loc)) {
                        const auto& tm = tiles->tiles();
                        MRPT_LOG_INFO_FMT("frame %zu: map tiles around (%.1f, %.1f) in use: %zu tiles, %zu points",
                                          r.index, tm.center().x(), tm.center().y(), tm.tilesLoaded(),
                                          tm.pointsLoaded());
                    }
                    out.addFrame(r, T, frame_out.map_points);
                    if (run_.save_observability_scan) {
                        obs_scan.add(frame_out.obs_points, frame_out.obs_labels);
                        if (summary_.frames % 200 == 199) obs_scan.write(obs_path);  // progressive
                    }
                    tally.addFrame(r, T, summary_);
                    // Log divergence when it starts and ends, not on every frame of a long episode.
                    if (r.diverged != in_divergence)
                        MRPT_LOG_WARN_FMT("frame %zu (t=%.3f): %s (%s), inlier ratio %.2f", r.index, r.t,
                                          r.diverged ? "diverged" : "tracking again",
                                          localization::divergenceName(r.diverged_reason), r.inlier_ratio);
                    in_divergence = r.diverged;
                    if (on_frame) on_frame(r);
                    break;
                }
            }
        }
        if (summary_.frames == 0) throw std::runtime_error(reader.noScanReason());
    } catch (const std::exception& e) {
        // Stopped on a fault the run cannot get past (a corrupt entry, time going backwards beyond
        // the reorder window, no scan at all): the frames so far are in trajectory.tum and
        // frames.csv already; summary.json says "failed" and why, then the error goes on to the
        // caller (one line on stderr, exit code 1).
        try {
            finish(oneLineError(e));
        } catch (const std::exception& e2) {
            MRPT_LOG_ERROR_FMT("could not write the outputs after the error: %s", oneLineError(e2).c_str());
        }
        throw;
    }
    if (summary_.health[2] == summary_.frames) {
        const std::string error = "all " + std::to_string(summary_.frames) + " frames of " + run_.rawlog +
                                  " are lost: no pose of the scans in " + run_.map +
                                  " was found (frames.csv health_reason says why per frame)";
        finish(error);
        throw std::runtime_error(error);
    }
    finish("");
    MRPT_LOG_INFO_FMT("%zu frames (%zu ok, %zu degraded, %zu lost), median %.2f ms, p95 %.2f ms per frame -> %s",
                      summary_.frames, summary_.health[0], summary_.health[1], summary_.health[2], summary_.ms_median,
                      summary_.ms_p95, run_.out.c_str());
    const auto& fa = summary_.flagged_axis;
    MRPT_LOG_INFO_FMT(
        "alignment risk: %zu frames flag a degenerate axis (x %zu, y %zu, z %zu, roll %zu, pitch %zu, "
        "yaw %zu); odom_alt prior in %zu frames; %zu flagged frames had no prior",
        summary_.flagged, fa[0], fa[1], fa[2], fa[3], fa[4], fa[5], summary_.with_prior,
        summary_.flagged_without_prior);
    return 0;
}

}  // namespace superloc::app
