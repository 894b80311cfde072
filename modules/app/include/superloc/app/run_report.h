// report.html of a superloc-localize run (doc/localizer.md "Outputs"): one self-contained page
// written at the end of the run beside trajectory.tum, frames.csv and summary.json. Inline SVG
// (SvgPlot) and a few lines of inline script, nothing fetched, so it opens in a browser as it is:
//   - the prior map from above (its points thinned to about one per pixel) with the trajectory
//     coloured by health (ok / degraded / lost)
//   - health and the flagged (degenerate) axes over time
//   - the odom_alt prior's weight per axis over time
//   - ms per frame over time
//   - summary.json's figures
// The page's script checks that every figure has a drawing and then sets
// <body data-report="drawn N">; a script error sets data-report="error" and shows the message in
// <pre id="errors"> (the browser test reads both).
#pragma once

#include <superloc/core/types.h>
#include <superloc/core/voxel.h>
#include <superloc/io/json_file.h>
#include <superloc/io/map_tiles.h>
#include <superloc/localization/frame_report.h>

#include <array>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

namespace superloc::app {

/// What the report keeps of a frame (a few dozen bytes, also for long runs).
struct ReportFrame {
    double t = 0;
    double x = 0, y = 0;               ///< [m] the written pose's position in the map
    int health = 0;                    ///< localization::Health: 0 ok, 1 degraded, 2 lost
    std::array<bool, 6> degenerate{};  ///< x y z roll pitch yaw
    bool prior_used = false;
    std::array<double, 6> prior_w{};   ///< diagonal information of the odom_alt prior
    double ms = 0;                     ///< wall time of the frame
    double sigma_xyz = 0, sigma_deg = 0;  ///< the pose's largest std [m], [deg] (0: none)
};

class RunReport {
 public:
    /// Prior map points, kept from above one per square cell of 1/800 of the first map's x-y
    /// extent (about a pixel of the top view; at least 2 cm), so that memory stays bounded for
    /// any map (at most 801² cells over the first map's extent). Call again for more (the
    /// tiles of a tiled map).
    void addMapPoints(const std::vector<Vec3f>& points);
    /// One frame, with `T` the pose written to trajectory.tum.
    void addFrame(const localization::FrameReport& r, const SE3d& T);
    /// Lines shown under the title, e.g. {"rawlog", path}.
    void setInputs(std::vector<std::pair<std::string, std::string>> inputs) { inputs_ = std::move(inputs); }

    /// The page. `summary`: summary.json's content; `title` names the run (its folder).
    std::string html(const io::Json& summary, const std::string& title) const;

    const std::vector<ReportFrame>& frames() const { return frames_; }
    size_t mapPointsKept() const { return map_x_.size(); }

 private:
    float cell_ = 0;  ///< [m] set by the first addMapPoints
    std::unordered_set<VoxelKey, VoxelKeyHash> cells_;
    std::vector<double> map_x_, map_y_;  ///< one point per cell
    std::vector<ReportFrame> frames_;
    std::vector<std::pair<std::string, std::string>> inputs_;
};

/// The tile files of `index` whose square comes within `radius` (x-y) of a frame's position: the
/// tiles a run loaded as it went (localization::MapTileFollower), for its report's map.
std::vector<std::string> tilesAlong(const io::MapTileIndex& index,
                                    const std::vector<ReportFrame>& frames, double radius);

}  // namespace superloc::app
