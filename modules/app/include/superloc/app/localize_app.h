// The superloc-localize application (doc/localizer.md) as a class that apps/ wraps and tests drive:
//   superloc-localize CONFIG.ini [--rawlog F] [--map F] [--method NAME] [--out DIR]
//       [--initial-pose "x y z qx qy qz qw" | --initial-pose-tum TUM] [--set sect.key=value]...
//       [--dump-config] [--quiet] [--help]
#pragma once

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/system/COutputLogger.h>
#include <superloc/io/rawlog.h>
#include <superloc/localization/localizer.h>
#include <superloc/app/run_outputs.h>
#include <superloc/map/prior_map.h>

#include <functional>
#include <string>
#include <vector>

namespace superloc::app {

/// Section [run]: inputs and outputs of the app. Paths given in the INI are relative to the INI
/// file's folder; paths given as flags are relative to the working directory.
struct RunParams : public mrpt::config::CLoadableOptions {
    std::string rawlog;            ///< input rawlog (--rawlog)
    std::string map;               ///< prior map file (--map)
    std::string out = "out";       ///< output folder (--out)
    std::string initial_pose;      ///< "x y z qx qy qz qw", T_map_lidar (--initial-pose)
    std::string initial_pose_tum;  ///< TUM file whose first pose is the initial pose
    double localized_map_voxel = 0.1;  ///< [m] voxel of localized_map.pcd (0 = keep all)
    bool save_localized_map = true;
    bool save_report = true;  ///< write report.html at the end of the run
    /// write observability_scan.ply (one coloured point per voxel of every correspondence: it
    /// grows with the area a run covers, so a long run's memory does too)
    bool save_observability_scan = true;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
};

/// Parses "x y z qx qy qz qw"; throws ConfigError naming `what` on anything else.
SE3d parsePoseString(const std::string& s, const std::string& what);

class LocalizeApp : public mrpt::system::COutputLogger {
   public:
    enum class Action { Run, Help, DumpConfig };

    LocalizeApp();
    /// Parses the command line and loads/validates every section. Throws ConfigError or
    /// std::runtime_error with a one-line message on bad input.
    Action initialize(int argc, const char* const* argv);
    /// Same, from an already-split argument list (without the program name).
    Action initialize(const std::vector<std::string>& args);

    /// Streams the rawlog through the localization::Localizer and writes the outputs. `on_frame` (optional)
    /// sees every report, e.g. for a progress display. Returns the process exit code.
    int run(const std::function<void(const localization::FrameReport&)>& on_frame = {});

    static std::string usage();
    /// The effective configuration as a commented INI (every section, defaults included).
    std::string dumpConfig() const;
    bool quiet() const { return quiet_; }
    const RunSummary& summary() const { return summary_; }
    const RunParams& runParams() const { return run_; }

   private:
    mrpt::config::CConfigFileMemory cfg_;
    std::string config_path_;
    RunParams run_;
    localization::LocalizerParams loc_;
    io::RawlogParams rawlog_;
    map::MapParams map_;
    bool quiet_ = false;
    RunSummary summary_;
};

}  // namespace superloc::app
