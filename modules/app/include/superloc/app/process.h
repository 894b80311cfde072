// Running the other SuperLoc apps as child processes (superloc-bench keeps modules independent
// by invoking superloc-sim / -import / -map / -localize rather than linking them).
#pragma once

#include <string>
#include <vector>

namespace superloc::app {

struct ProcessResult {
    bool started = false;    ///< the executable could be run
    int exit_code = -1;      ///< exit status (128 + signal when killed by a signal)
    bool timed_out = false;  ///< killed after the timeout
    double wall_s = 0;       ///< [s] wall time
    /// [MiB] peak resident memory of the child's program (VmHWM, read every 20 ms while it runs)
    double peak_rss_mb = 0;
    bool ok() const { return started && !timed_out && exit_code == 0; }
};

/// How many children runProcess can run at once and still kill on SIGINT/SIGTERM.
constexpr unsigned kMaxChildren = 1024;

/// Runs argv[0] with argv, stdout and stderr appended to `log_path`; kills the child (SIGKILL,
/// by its pid) after `timeout_s` seconds (<= 0: no limit). Several threads may call it at once
/// (superloc-bench --jobs): argv[0] should be a path (findTool), as the child between fork and
/// exec only redirects its output and calls exec.
ProcessResult runProcess(const std::vector<std::string>& argv, const std::string& log_path,
                         double timeout_s);

/// Installs SIGINT/SIGTERM handlers that kill the running children of runProcess (by their pids)
/// and exit with 128 + signal, so stopping superloc-bench does not leave a localizer running.
void killChildOnTermination();

/// Path of a SuperLoc executable: `dir/name`, then `dir/../name/name` (the build tree's
/// apps/<name>/<name>), then the PATH. Empty when not found.
std::string findTool(const std::string& name, const std::string& dir);

/// Path of the running executable (/proc/self/exe).
std::string selfExe();

/// Folder of the running executable.
std::string selfDir();

}  // namespace superloc::app
