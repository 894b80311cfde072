// The fault suite's tools (test_faults_*.cpp): rewrite a rawlog item by item with a fault in it,
// run the superloc-localize executable on it (the exit code and stderr are part of the contract),
// and read back what it wrote (trajectory.tum, frames.csv, summary.json).
#pragma once

#include <gtest/gtest.h>
#include <mrpt/system/COutputLogger.h>
#include <superloc/core/se3.h>
#include <superloc/io/json_file.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/tum.h>
#include <superloc_testing/testing.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace superloc::testing {

/// Writes one typed item back as the observation it was read from (scans as
/// CObservationPointCloud: the reader derives the per-point time from the azimuth again).
inline void writeItem(io::RawlogWriter& w, const io::RawlogItem& it, const io::RawlogParams& rp = {}) {
    switch (it.kind) {
        case io::RawlogItem::Kind::Lidar: w.writeScan(it.scan(), it.scan().label); break;
        case io::RawlogItem::Kind::Imu: w.writeImu(it.imu()); break;
        case io::RawlogItem::Kind::OdomAlt: w.writePose(it.pose(), rp.odom_alt_label); break;
        case io::RawlogItem::Kind::GroundTruth: w.writePose(it.pose(), rp.gt_label); break;
    }
}

/// Copies `in` (the scans `scans` of it, in time order) to `out`, passing each item to `edit`,
/// which writes what it wants (nothing drops the item; writeItem(w, it) keeps it). Returns the
/// number of LiDAR scans read.
inline size_t rewriteRawlog(const std::string& in, const std::string& out, const std::string& scans,
                            const std::function<void(io::RawlogItem&, io::RawlogWriter&)>& edit) {
    io::RawlogParams rp;
    rp.scans = scans;
    io::RawlogReader r(in, rp);
    r.logger().setMinLoggingLevel(mrpt::system::LVL_ERROR);
    io::RawlogWriter w(out);
    io::RawlogItem it;
    size_t n = 0;
    while (r.next(it)) {
        n += it.kind == io::RawlogItem::Kind::Lidar;
        edit(it, w);
    }
    w.close();
    return n;
}

/// frames.csv as columns by header name (every value kept as text).
struct FramesCsv {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    size_t col(const std::string& name) const {
        for (size_t i = 0; i < header.size(); ++i)
            if (header[i] == name) return i;
        ADD_FAILURE() << "frames.csv has no column " << name;
        return 0;
    }
    double num(size_t row, const std::string& name) const { return std::stod(rows.at(row).at(col(name))); }
    const std::string& text(size_t row, const std::string& name) const { return rows.at(row).at(col(name)); }
};

inline std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> v;
    std::string cell;
    std::istringstream is(line);
    while (std::getline(is, cell, ',')) v.push_back(cell);
    if (!line.empty() && line.back() == ',') v.emplace_back();
    return v;
}

inline FramesCsv loadFramesCsv(const std::string& path) {
    FramesCsv f;
    std::ifstream in(path);
    std::string line;
    if (!std::getline(in, line)) return f;
    f.header = splitCsv(line);
    while (std::getline(in, line)) {
        f.rows.push_back(splitCsv(line));
        EXPECT_EQ(f.rows.back().size(), f.header.size()) << path << ": a truncated row: " << line;
    }
    EXPECT_TRUE(line.empty() || in.eof()) << path;
    return f;
}

/// One superloc-localize run as a process, and what it left behind.
struct FaultRun {
    int exit_code = -1;
    std::string stderr_text;
    std::string dir;
    Trajectory trajectory;   ///< trajectory.tum
    FramesCsv frames;        ///< frames.csv
    nlohmann::json summary;  ///< summary.json (null when missing or not JSON: the test fails then)
    /// Translation error [m] of every written pose against the ground truth (NaN without one).
    std::vector<double> err_m;
    double errAt(double t) const {
        for (size_t i = 0; i < trajectory.size(); ++i)
            if (std::abs(trajectory[i].t - t) < 1e-4) return err_m[i];
        return NAN;
    }
};

inline std::string readText(const std::string& path) {
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

/// `superloc-localize ini/localize.ini ARGS --out DIR --quiet` (under `timeout`, so that a hang is
/// a failure and not a stuck CI job), then reads DIR's outputs and checks the invariants every
/// run keeps, fault or not: each processed frame is one line in trajectory.tum and one row in
/// frames.csv, the same frames in the same order; summary.json is JSON whose frame count agrees;
/// stderr is empty on success and one line on failure.
inline FaultRun runLocalize(const std::vector<std::string>& args, const std::string& dir, const std::string& gt_tum) {
    namespace fs = std::filesystem;
    FaultRun r;
    r.dir = dir;
    std::string cmd = "timeout 300 " + appPath("superloc-localize") + " " + sourcePath("ini/localize.ini");
    for (const auto& a : args) cmd += " '" + a + "'";
    cmd += " --out " + dir + " --quiet > " + dir + ".stdout 2> " + dir + ".stderr";
    const int st = std::system(cmd.c_str());
    r.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    r.stderr_text = readText(dir + ".stderr");
    EXPECT_NE(r.exit_code, 124) << "superloc-localize hung: " << cmd;
    if (r.exit_code == 0) {
        EXPECT_EQ(r.stderr_text, "") << "a successful run prints nothing on stderr with --quiet";
    } else {
        // One line, the tool's name first: "superloc-localize: error: <reason>\n".
        EXPECT_EQ(std::count(r.stderr_text.begin(), r.stderr_text.end(), '\n'), 1) << r.stderr_text;
        EXPECT_EQ(r.stderr_text.rfind("superloc-localize: error: ", 0), 0u) << r.stderr_text;
    }
    if (fs::exists(dir + "/trajectory.tum")) r.trajectory = io::loadTum(dir + "/trajectory.tum");
    r.frames = loadFramesCsv(dir + "/frames.csv");
    EXPECT_EQ(r.frames.rows.size(), r.trajectory.size()) << "trajectory.tum and frames.csv disagree";
    for (size_t i = 0; i < std::min(r.frames.rows.size(), r.trajectory.size()); ++i) {
        EXPECT_NEAR(r.frames.num(i, "t"), r.trajectory[i].t, 1e-6) << "row " << i;
        EXPECT_EQ(r.frames.num(i, "index"), static_cast<double>(i)) << "row " << i;
        if (i > 0) {
            EXPECT_GT(r.trajectory[i].t, r.trajectory[i - 1].t) << "time goes backwards at row " << i;
        }
    }
    try {
        r.summary = nlohmann::json::parse(readText(dir + "/summary.json"));
        EXPECT_EQ(r.summary.at("frames").get<size_t>(), r.trajectory.size());
        EXPECT_EQ(r.summary.at("status").get<std::string>(), r.exit_code == 0 ? "ok" : "failed");
    } catch (const std::exception& e) {
        ADD_FAILURE() << dir << "/summary.json: " << e.what();
        r.summary = nullptr;
    }
    if (!gt_tum.empty()) {
        const Trajectory gt = io::loadTum(gt_tum);
        for (const auto& e : r.trajectory) {
            const auto g = interpolateAt(gt, e.t, 1.5, 1e-3);
            r.err_m.push_back(g ? translationDistance(*g, e.pose) : NAN);
        }
    }
    return r;
}

/// Largest value of `v` over the rows where `keep(t)` holds (0 when none).
inline double maxWhere(const FaultRun& r, const std::function<bool(double)>& keep) {
    double m = 0;
    for (size_t i = 0; i < r.trajectory.size(); ++i)
        if (keep(r.trajectory[i].t)) m = std::max(m, r.err_m[i]);
    return m;
}

}  // namespace superloc::testing
