// The superloc-import application (doc/your-data.md, doc/io.md):
//   superloc-import (--kitti DIR | --pcd-dir DIR | --rosbag BAG [--list]) [--poses TUM]
//       [--times FILE] [--imu-csv F] [--odom-csv F] [--gt-tum F] [--config INI]
//       [--set rosbag.key=value]... [--dump-config] [--quiet] --out FILE.rawlog
#pragma once

#include <string>
#include <vector>

namespace superloc::app {

class ImportApp {
 public:
    /// Parses the arguments (without the program name), imports, prints a one-line summary
    /// (or the help text, the bag's topics, the effective [rosbag] section) on stdout. Returns
    /// the exit code; throws ConfigError / std::runtime_error with a one-line reason.
    static int run(const std::vector<std::string>& args);
    static std::string usage();
};

}  // namespace superloc::app
