// Importers of scan folders (KITTI velodyne/*.bin, or *.pcd) into rawlogs: one
// CObservationPointCloud (CPointsMapXYZI) per scan, plus a `gt` CObservationRobotPose per scan
// when poses are given. Streams one scan at a time.
#include <superloc/io/importers.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/tum.h>

#include "extras_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>

namespace superloc::io {

namespace fs = std::filesystem;

namespace {

/// Files of `dir` with extension `ext` (case-insensitive), sorted by name.
std::vector<std::string> listFiles(const std::string& dir, const std::string& ext) {
    if (!fs::is_directory(dir)) throw std::runtime_error(dir + ": folder not found");
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (!e.is_regular_file()) continue;
        std::string x = e.path().extension().string();
        std::transform(x.begin(), x.end(), x.begin(),
                       [](unsigned char c) { return std::tolower(c); });
        if (x == ext) files.push_back(e.path().string());
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) throw std::runtime_error(dir + ": no *" + ext + " files");
    return files;
}

/// One time [s] per line ('#' comments and blank lines skipped), strictly increasing.
std::vector<double> loadTimes(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open times file");
    std::vector<double> t;
    std::string line;
    size_t lineno = 0;
    while (std::getline(in, line)) {
        ++lineno;
        const size_t a = line.find_first_not_of(" \t\r");
        if (a == std::string::npos || line[a] == '#') continue;
        const size_t b = line.find_last_not_of(" \t\r");
        const std::string s = line.substr(a, b - a + 1);
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (end != s.c_str() + s.size() || !std::isfinite(v))
            throw std::runtime_error(path + ":" + std::to_string(lineno) +
                                     ": not a time in seconds: '" + s + "'");
        if (!t.empty() && v <= t.back())
            throw std::runtime_error(path + ":" + std::to_string(lineno) +
                                     ": time does not increase");
        t.push_back(v);
    }
    return t;
}

/// Pose of each scan: by index when there are as many poses as scans, else by timestamp
/// (within 1 ms); scans without a pose get nullopt.
std::vector<std::optional<SE3d>> matchPoses(const Trajectory& traj,
                                            const std::vector<double>& times,
                                            const std::string& tum_path) {
    std::vector<std::optional<SE3d>> out(times.size());
    if (traj.size() == times.size()) {
        for (size_t i = 0; i < times.size(); ++i) out[i] = traj[i].pose;
        return out;
    }
    size_t j = 0, matched = 0;
    for (size_t i = 0; i < times.size(); ++i) {
        while (j + 1 < traj.size() && traj[j + 1].t <= times[i] + 1e-3) ++j;
        for (size_t k = j; k < std::min(traj.size(), j + 2); ++k)
            if (std::abs(traj[k].t - times[i]) < 1e-3) {
                out[i] = traj[k].pose;
                ++matched;
                break;
            }
    }
    if (matched == 0)
        throw std::runtime_error(tum_path + ": " + std::to_string(traj.size()) + " poses for " +
                                 std::to_string(times.size()) +
                                 " scans and no timestamp matches a scan time");
    return out;
}

ImportResult writeRawlog(const std::vector<std::string>& files, CloudFormat format,
                         const std::vector<double>& times,
                         const std::vector<std::optional<SE3d>>& poses,
                         const std::string& out_rawlog, const ProgressFn& progress,
                         const ImportExtras& extras) {
    ImportResult r;
    RawlogWriter w(out_rawlog);
    detail::ExtrasWriter ex(extras, r);
    for (size_t i = 0; i < files.size(); ++i) {
        ex.flushUntil(w, times[i]);
        size_t dropped = 0;
        PointCloud c = loadPointCloud(files[i], format, &dropped);
        r.dropped_points += dropped;
        if (c.empty()) {  // no valid point: not a scan (its gt pose is still written)
            if (r.empty_scans++ == 0) r.first_empty = files[i];
        }
        Scan s;
        s.t = times[i];
        s.points = std::move(c.points);
        s.intensity = std::move(c.intensity);
        if (!s.empty()) {
            w.writeScan(s);
            ++r.scans;
            r.points += s.size();
        }
        if (!poses.empty() && poses[i]) {
            PoseStamped p;
            p.t = times[i];
            p.pose = *poses[i];
            w.writePose(p, "gt");
            ++r.gt_poses;
        }
        if (progress) progress(i + 1, files.size());
    }
    ex.flushAll(w);
    w.close();
    return r;
}

void checkCount(size_t n_times, size_t n_scans, const std::string& what) {
    if (n_times != n_scans)
        throw std::runtime_error(what + ": " + std::to_string(n_times) + " entries for " +
                                 std::to_string(n_scans) + " scans (need one per scan)");
}

}  // namespace

ImportResult importKitti(const std::string& dir, const std::string& poses_tum,
                         const std::string& times_file, const std::string& out_rawlog,
                         const ProgressFn& progress, const ImportExtras& extras) {
    const auto files = listFiles((fs::path(dir) / "velodyne").string(), ".bin");
    const std::string tpath =
        times_file.empty() ? (fs::path(dir) / "times.txt").string() : times_file;
    std::optional<Trajectory> traj;
    if (!poses_tum.empty()) traj = loadTum(poses_tum);
    std::vector<double> times;
    if (fs::exists(tpath) || !times_file.empty()) {
        times = loadTimes(tpath);
        checkCount(times.size(), files.size(), tpath);
    } else if (traj) {
        checkCount(traj->size(), files.size(), poses_tum);  // no times.txt: the poses' times
        for (const auto& p : *traj) times.push_back(p.t);
    } else {
        throw std::runtime_error(tpath + ": not found (give --times FILE or --poses TUM)");
    }
    std::vector<std::optional<SE3d>> poses;
    if (traj) poses = matchPoses(*traj, times, poses_tum);
    return writeRawlog(files, CloudFormat::KittiBin, times, poses, out_rawlog, progress, extras);
}

ImportResult importPcdFolder(const std::string& dir, const std::string& poses_tum,
                             const std::string& times_file, const std::string& out_rawlog,
                             const ProgressFn& progress, const ImportExtras& extras) {
    const auto files = listFiles(dir, ".pcd");
    std::optional<Trajectory> traj;
    if (!poses_tum.empty()) traj = loadTum(poses_tum);
    std::vector<double> times;
    if (!times_file.empty()) {
        times = loadTimes(times_file);
        checkCount(times.size(), files.size(), times_file);
    } else if (traj) {
        checkCount(traj->size(), files.size(), poses_tum);
        for (size_t i = 0; i < traj->size(); ++i) {
            if (i > 0 && (*traj)[i].t <= (*traj)[i - 1].t)
                throw std::runtime_error(
                    poses_tum + ": pose " + std::to_string(i + 1) +
                    " repeats the previous timestamp (scan times must increase)");
            times.push_back((*traj)[i].t);
        }
    } else {
        throw std::runtime_error(
            dir + ": a PCD folder needs --poses TUM or --times FILE for the scan times");
    }
    std::vector<std::optional<SE3d>> poses;
    if (traj) poses = matchPoses(*traj, times, poses_tum);
    return writeRawlog(files, CloudFormat::PcdBinary, times, poses, out_rawlog, progress, extras);
}

}  // namespace superloc::io
