// TUM trajectories: one "t x y z qx qy qz qw" per line; '#' lines are comments. evo reads them.
#pragma once

#include <superloc/core/types.h>

#include <fstream>
#include <string>

namespace superloc::io {

/// Loads a TUM file. Throws std::runtime_error "FILE:LINE: ..." on a malformed line, a
/// non-finite value, a timestamp going backwards or one repeated.
Trajectory loadTum(const std::string& path);

/// Saves a whole trajectory (full double precision).
void saveTum(const std::string& path, const Trajectory& traj);

/// Appends poses one at a time and flushes each line, so a run that stops keeps what it wrote.
class TumWriter {
 public:
    explicit TumWriter(const std::string& path, const std::string& header_comment = "");
    void write(const PoseStamped& p);
    void write(double t, const SE3d& pose);

 private:
    std::string path_;
    std::ofstream out_;
};

/// One TUM line for a pose.
std::string formatTumLine(double t, const SE3d& pose);

}  // namespace superloc::io
