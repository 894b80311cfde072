// A benchmark suite (doc/evaluation.md): sequences x methods, read from a suite INI, and the
// command lines of the apps that prepare and run each case (doc/design.md#9-command-line).
//
//   [suite]
//   methods         = superloc icp passive eigen_remap ndt
//   sequences       = corridor kitti00-mini
//   localize_config = ../localize.ini        ; relative to the suite file
//   localize_set    = localization.max_frames=200   ; extra --set for every localize run
//   timeout         = 900                    ; [s] per child process
//   [eval]  ... (eval::EvalParams keys)
//   [seq.corridor]
//   type = sim            config = ../sim/corridor.ini   seed = 1   sim_set = sim.duration=20
//   (or seeds = 1 2 3: one sequence NAME_sN per seed, grouped under NAME in the report)
//   [seq.kitti00-mini]
//   type = kitti          data = kitti00-mini   gt = gt_velodyne_tum.txt   prior_voxel = 0.1
//   [seq.campus-ouster]
//   type = pcd            data = campus-ouster  scans = scans  gt = gt_tum.txt
#pragma once

#include <superloc/eval/eval_params.h>

#include <string>
#include <vector>

namespace superloc::app {

struct SequenceSpec {
    enum class Kind { Sim, Kitti, PcdDir };
    std::string name;
    /// The suite's sequence this one came from: `name`, or NAME for the NAME_sN of `seeds`
    std::string group;
    Kind kind = Kind::Sim;
    std::string config;                 ///< sim: scenario INI (absolute)
    int seed = 1;                       ///< sim: --seed
    std::vector<std::string> sim_sets;  ///< sim: extra --set section.key=value
    std::string data;                   ///< real: data folder (absolute)
    std::string scans;                  ///< pcd: scan folder (absolute)
    std::string gt;                     ///< real: GT TUM (absolute)
    double prior_voxel = 0.1;           ///< [m] real: voxel of the prior map built from the scans
    double gt_map_voxel = 0.02;         ///< [m] real: voxel of the GT map built from the scans
    /// real: the scans the prior map is built from and the scans localized in it ([rawlog]
    /// scans syntax). Never the same scans (the honest protocol, doc/design.md#8-evaluation), unless `circular`.
    std::string map_scans = "even", localize_scans = "odd";
    bool circular = false;              ///< real: a labelled sanity check with map_scans == localize_scans
    std::vector<std::string> localize_sets;  ///< extra --set for this sequence's localize runs
    /// The folder of its data under DIR/data when not its own name: that of the first sequence
    /// of the suite that simulates the same data (same config, seed and sim_set; it differs only
    /// in its localize_set), whose data it shares. Empty: its own.
    std::string data_name;
};

struct SuiteSpec {
    std::string path;  ///< the suite file
    std::vector<std::string> methods;
    std::string localize_config;  ///< absolute
    std::vector<std::string> localize_sets;
    double timeout_s = 900;
    eval::EvalParams eval;
    std::vector<SequenceSpec> sequences;
};

/// Reads a suite INI. Relative `config`/`localize_config` paths are taken from the suite file's
/// folder, `data` from `data_dir` (../shared/data). Throws ConfigError naming the file, section
/// and key on an unknown key, a missing required key, a bad type or a missing file.
SuiteSpec loadSuite(const std::string& path, const std::string& data_dir);

/// Paths of one sequence's prepared data under the suite's output folder.
struct SequenceFiles {
    std::string dir, rawlog, gt_tum, gt_map, prior_map;
};
SequenceFiles sequenceFiles(const SequenceSpec& seq, const std::string& out_dir);

/// Command lines (argv) of the apps, doc/design.md#9-command-line. `tool` is the executable's path.
std::vector<std::string> simCommand(const std::string& tool, const SequenceSpec& seq,
                                    const std::string& dir);
std::vector<std::string> importCommand(const std::string& tool, const SequenceSpec& seq,
                                       const std::string& rawlog);
/// superloc-map over the scans `scans` ([rawlog] scans syntax; "all" adds no flag).
std::vector<std::string> mapCommand(const std::string& tool, const std::string& rawlog,
                                    const std::string& poses, double voxel,
                                    const std::string& out, const std::string& scans = "all");
std::vector<std::string> localizeCommand(const std::string& tool, const SuiteSpec& suite,
                                         const SequenceSpec& seq, const std::string& method,
                                         const SequenceFiles& files, const std::string& out_dir);

/// `s` as one word of a POSIX shell: as it is when made of [A-Za-z0-9_./:=@%+,-] only, else in
/// single quotes (a ' inside as '\'').
std::string shellQuote(const std::string& s);

/// argv as a shell command line (each argument through shellQuote): for log lines and the
/// commands of superloc-bench --plan.
std::string joinCommand(const std::vector<std::string>& argv);

/// The blank-separated words of an INI value or a command-line list ("superloc icp").
std::vector<std::string> splitWords(const std::string& s);

}  // namespace superloc::app
