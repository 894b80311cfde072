#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc/app/ini_sections.h>
#include <superloc/app/suite.h>
#include <superloc/io/rawlog.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace superloc::app {
namespace fs = std::filesystem;
namespace {

/// Rejects keys of `section` not in `known`.
void checkKeys(const mrpt::config::CConfigFileBase& c, const std::string& section,
               const std::set<std::string>& known, const std::string& file) {
    std::vector<std::string> keys;
    c.getAllKeys(section, keys);
    for (const auto& k : keys)
        if (!known.count(stripIniValue(k))) {
            std::string list;
            for (const auto& n : known) list += (list.empty() ? "" : ", ") + n;
            throw ConfigError(file + ": unknown key '" + k + "' in section [" + section +
                              "] (known keys: " + list + ")");
        }
}

std::string value(const mrpt::config::CConfigFileBase& c, const std::string& section,
                  const std::string& key, const std::string& def = "") {
    return stripIniValue(c.read_string(section, key, def));
}

double number(const mrpt::config::CConfigFileBase& c, const std::string& section,
              const std::string& key, double def, const std::string& file) {
    const std::string v = value(c, section, key);
    if (v.empty()) return def;
    double d;
    if (!parseDouble(v, d))
        throw ConfigError(file + ": [" + section + "] " + key + " = '" + v + "' is not a number");
    return d;
}

std::string existing(const fs::path& p, const std::string& what) {
    if (!fs::exists(p)) throw ConfigError(what + ": " + p.string() + " does not exist");
    return fs::absolute(p).lexically_normal().string();
}

}  // namespace

SuiteSpec loadSuite(const std::string& path, const std::string& data_dir) {
    mrpt::config::CConfigFileMemory c;
    loadIniFile(c, path, "suite file");
    const fs::path base = fs::absolute(path).parent_path();
    SuiteSpec s;
    s.path = path;
    checkSections(c, suiteSections(), path, {});
    if (!c.sectionExists("suite")) throw ConfigError(path + ": missing section [suite]");
    checkKeys(c, "suite", {"methods", "sequences", "localize_config", "localize_set", "timeout"},
              path);
    s.methods = splitWords(value(c, "suite", "methods"));
    if (s.methods.empty())
        throw ConfigError(path + ": [suite] methods is required (e.g. superloc icp)");
    const std::string lc = value(c, "suite", "localize_config");
    if (lc.empty()) throw ConfigError(path + ": [suite] localize_config is required");
    s.localize_config = existing(base / lc, path + ": [suite] localize_config");
    s.localize_sets = splitWords(value(c, "suite", "localize_set"));
    const auto checkSets = [&](const std::vector<std::string>& sets, const std::string& where) {
        for (const auto& kv : sets) {
            try {
                mrpt::config::CConfigFileMemory scratch;
                applyOverride(scratch, kv);
                checkSections(scratch, localizeSections(), "", {kv});
            } catch (const ConfigError& e) {
                throw ConfigError(where + " localize_set: " + e.what());
            }
        }
    };
    checkSets(s.localize_sets, path + ": [suite]");
    s.timeout_s = number(c, "suite", "timeout", s.timeout_s, path);
    s.eval = loadParams<eval::EvalParams>(c, "eval", path);

    const auto names = splitWords(value(c, "suite", "sequences"));
    if (names.empty()) throw ConfigError(path + ": [suite] sequences is required");
    for (const auto& name : names) {
        const std::string sec = "seq." + name;
        if (!c.sectionExists(sec))
            throw ConfigError(path + ": [suite] sequences lists '" + name + "' but there is no [" +
                              sec + "]");
        checkKeys(c, sec,
                  {"type", "config", "seed", "seeds", "sim_set", "data", "scans", "gt", "prior_voxel",
                   "gt_map_voxel", "localize_set", "map_scans", "localize_scans", "circular"},
                  path);
        SequenceSpec q;
        q.name = name;
        const std::string type = value(c, sec, "type");
        const std::string where = path + ": [" + sec + "]";
        q.localize_sets = splitWords(value(c, sec, "localize_set"));
        checkSets(q.localize_sets, where);
        if (type == "sim") {
            q.kind = SequenceSpec::Kind::Sim;
            q.config = existing(base / value(c, sec, "config"), where + " config");
            q.seed = static_cast<int>(number(c, sec, "seed", 1, path));
            if (long long whole = 0; !value(c, sec, "seed").empty() &&
                                     (!parseInteger(value(c, sec, "seed"), whole) || whole < 0))
                throw ConfigError(where + " seed = '" + value(c, sec, "seed") +
                                  "' is not a seed (a whole number >= 0)");
            q.sim_sets = splitWords(value(c, sec, "sim_set"));
        } else if (type == "kitti" || type == "pcd") {
            q.kind = type == "kitti" ? SequenceSpec::Kind::Kitti : SequenceSpec::Kind::PcdDir;
            if (value(c, sec, "data").empty() || value(c, sec, "gt").empty())
                throw ConfigError(where + " needs data = FOLDER and gt = TUM");
            q.data = existing(fs::path(data_dir) / value(c, sec, "data"), where + " data");
            q.gt = existing(fs::path(q.data) / value(c, sec, "gt"), where + " gt");
            if (q.kind == SequenceSpec::Kind::PcdDir)
                q.scans =
                    existing(fs::path(q.data) / value(c, sec, "scans", "scans"), where + " scans");
            q.prior_voxel = number(c, sec, "prior_voxel", q.prior_voxel, path);
            q.gt_map_voxel = number(c, sec, "gt_map_voxel", q.gt_map_voxel, path);
            q.map_scans = value(c, sec, "map_scans", q.map_scans);
            q.localize_scans = value(c, sec, "localize_scans", q.localize_scans);
            q.circular = number(c, sec, "circular", 0, path) != 0;
            for (const auto* k : {&q.map_scans, &q.localize_scans}) {
                io::RawlogParams rp;
                rp.scans = *k;
                try {
                    rp.scanSelection();
                } catch (const std::exception& e) {
                    throw ConfigError(where + ": " + e.what());
                }
            }
            if (q.map_scans == q.localize_scans && !q.circular)
                throw ConfigError(where + " map_scans = localize_scans = '" + q.map_scans +
                                  "': the prior map would hold the localized scans (set circular = 1 "
                                  "for a labelled sanity check)");
        } else {
            throw ConfigError(where + " type = '" + type + "': expected sim, kitti or pcd");
        }
        q.group = name;
        const auto seeds = splitWords(value(c, sec, "seeds"));
        if (!seeds.empty() && q.kind != SequenceSpec::Kind::Sim)
            throw ConfigError(where + " seeds: only a simulated sequence (type = sim) has seeds");
        if (!seeds.empty() && !value(c, sec, "seed").empty())
            throw ConfigError(where + ": give seed or seeds, not both");
        if (seeds.empty()) {
            s.sequences.push_back(q);
            continue;
        }
        // One sequence per seed, NAME_sN, grouped under NAME (the report's mean over seeds).
        for (const auto& w : seeds) {
            SequenceSpec one = q;
            try {
                size_t used = 0;
                one.seed = std::stoi(w, &used);
                if (used != w.size() || one.seed < 0) throw std::invalid_argument(w);
            } catch (const std::exception&) {
                throw ConfigError(where + " seeds: '" + w + "' is not a seed (whole numbers >= 0, e.g. seeds = 1 2 3)");
            }
            one.name = name + "_s" + w;
            s.sequences.push_back(one);
        }
    }
    // Sequences that simulate the same data (the same world with other localize settings, e.g.
    // with and without IMU) share one simulation.
    std::map<std::string, std::string> simulated;
    for (auto& q : s.sequences) {
        if (q.kind != SequenceSpec::Kind::Sim) continue;
        std::string key = q.config + '\n' + std::to_string(q.seed);
        for (const auto& w : q.sim_sets) key += '\n' + w;
        if (const auto& first = simulated.emplace(key, q.name).first->second; first != q.name) q.data_name = first;
    }
    return s;
}

SequenceFiles sequenceFiles(const SequenceSpec& seq, const std::string& out_dir) {
    SequenceFiles f;
    const fs::path d = fs::path(out_dir) / "data" / (seq.data_name.empty() ? seq.name : seq.data_name);
    f.dir = d.string();
    f.rawlog = (d / "sequence.rawlog").string();
    if (seq.kind == SequenceSpec::Kind::Sim) {
        f.gt_tum = (d / "gt_tum.txt").string();
        f.gt_map = (d / "gt_map.ply").string();
    } else {
        f.gt_tum = seq.gt;
        f.gt_map = (d / "gt_map.pcd").string();
    }
    f.prior_map = (d / "prior_map.pcd").string();
    return f;
}

std::vector<std::string> simCommand(const std::string& tool, const SequenceSpec& seq,
                                    const std::string& dir) {
    std::vector<std::string> a = {tool, seq.config, "--out",
                                  dir,  "--seed",   std::to_string(seq.seed)};
    for (const auto& s : seq.sim_sets) a.insert(a.end(), {"--set", s});
    return a;
}

std::vector<std::string> importCommand(const std::string& tool, const SequenceSpec& seq,
                                       const std::string& rawlog) {
    if (seq.kind == SequenceSpec::Kind::Kitti)
        return {tool, "--kitti", seq.data, "--poses", seq.gt, "--out", rawlog, "--quiet"};
    return {tool, "--pcd-dir", seq.scans, "--poses", seq.gt, "--out", rawlog, "--quiet"};
}

std::vector<std::string> mapCommand(const std::string& tool, const std::string& rawlog,
                                    const std::string& poses, double voxel,
                                    const std::string& out, const std::string& scans) {
    std::ostringstream v;
    v << voxel;
    std::vector<std::string> a = {tool, "--rawlog", rawlog, "--poses", poses, "--voxel", v.str(), "--out", out};
    if (scans != "all") a.insert(a.end(), {"--set", "rawlog.scans=" + scans});
    return a;
}

std::vector<std::string> localizeCommand(const std::string& tool, const SuiteSpec& suite,
                                         const SequenceSpec& seq, const std::string& method,
                                         const SequenceFiles& files, const std::string& out_dir) {
    std::vector<std::string> a = {tool,
                                  suite.localize_config,
                                  "--rawlog",
                                  files.rawlog,
                                  "--map",
                                  files.prior_map,
                                  "--method",
                                  method,
                                  "--out",
                                  out_dir,
                                  "--initial-pose-tum",
                                  files.gt_tum,
                                  "--quiet"};
    if (seq.kind != SequenceSpec::Kind::Sim && seq.localize_scans != "all")
        a.insert(a.end(), {"--set", "rawlog.scans=" + seq.localize_scans});
    for (const auto& s : suite.localize_sets) a.insert(a.end(), {"--set", s});
    for (const auto& s : seq.localize_sets) a.insert(a.end(), {"--set", s});
    return a;
}

std::string shellQuote(const std::string& s) {
    const bool plain = !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) {
        return std::isalnum(c) || (c != 0 && std::strchr("_./:=@%+,-", c) != nullptr);
    });
    if (plain) return s;
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

std::string joinCommand(const std::vector<std::string>& argv) {
    std::string s;
    for (const auto& a : argv) s += (s.empty() ? "" : " ") + shellQuote(a);
    return s;
}

std::vector<std::string> splitWords(const std::string& s) {
    std::vector<std::string> out;
    std::istringstream ss(s);
    for (std::string w; ss >> w;) out.push_back(w);
    return out;
}

}  // namespace superloc::app
