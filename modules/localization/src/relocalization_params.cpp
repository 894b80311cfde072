#include <mrpt/config/CConfigFileBase.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/localization/relocalization.h>

#include <cmath>

namespace superloc::localization {

const char* relocOutcomeName(RelocOutcome o) {
    switch (o) {
        case RelocOutcome::None: return "";
        case RelocOutcome::Accepted: return "accepted";
        case RelocOutcome::NotBetter: return "not_better";
        case RelocOutcome::TooFar: return "too_far";
        case RelocOutcome::Ambiguous: return "ambiguous";
        case RelocOutcome::Failed: return "failed";
        case RelocOutcome::Deferred: return "deferred";
    }
    return "?";
}

void RelocalizationParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
    MRPT_LOAD_CONFIG_VAR(enabled, bool, c, s);
    MRPT_LOAD_CONFIG_VAR(local_after_lost, int, c, s);
    MRPT_LOAD_CONFIG_VAR(global_after_lost, int, c, s);
    MRPT_LOAD_CONFIG_VAR(local_radius, double, c, s);
    MRPT_LOAD_CONFIG_VAR(local_radius_rate, double, c, s);
    MRPT_LOAD_CONFIG_VAR(local_yaw_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(verify_hypotheses, int, c, s);
    MRPT_LOAD_CONFIG_VAR(hypothesis_features, int, c, s);
    MRPT_LOAD_CONFIG_VAR(accept_inlier_ratio, double, c, s);
    MRPT_LOAD_CONFIG_VAR(ambiguity_ratio, double, c, s);
    MRPT_LOAD_CONFIG_VAR(distinct_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(distinct_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(doubt_max_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(doubt_max_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(doubt_search_period, double, c, s);
    out_of_map = c.read_string(s, "out_of_map", out_of_map);
    MRPT_LOAD_CONFIG_VAR(start_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(start_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(start_ring_yaws, int, c, s);
    MRPT_LOAD_CONFIG_VAR(start_refine_ratio, double, c, s);
    MRPT_LOAD_CONFIG_VAR(start_distinct_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(start_distinct_deg, double, c, s);
    MRPT_LOAD_CONFIG_VAR(track_candidates, int, c, s);
    MRPT_LOAD_CONFIG_VAR(track_min_frames, int, c, s);
    MRPT_LOAD_CONFIG_VAR(track_ratio, double, c, s);
    MRPT_LOAD_CONFIG_VAR(track_consistent_frames, int, c, s);
    MRPT_LOAD_CONFIG_VAR(track_lead, double, c, s);
    MRPT_LOAD_CONFIG_VAR(track_probe_xyz, double, c, s);
    MRPT_LOAD_CONFIG_VAR(track_search_every, int, c, s);
    MRPT_LOAD_CONFIG_VAR(track_max_frames, int, c, s);
    MRPT_LOAD_CONFIG_VAR(track_max_ms, double, c, s);
}

void RelocalizationParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
    MRPT_SAVE_CONFIG_VAR_COMMENT(enabled, "search again when lost (every method); false: stay lost");
    MRPT_SAVE_CONFIG_VAR_COMMENT(local_after_lost, "consecutive lost frames before a local search");
    MRPT_SAVE_CONFIG_VAR_COMMENT(global_after_lost, "consecutive lost frames before a global search");
    MRPT_SAVE_CONFIG_VAR_COMMENT(local_radius, "[m] local search radius around the last tracked pose");
    MRPT_SAVE_CONFIG_VAR_COMMENT(local_radius_rate, "[m/s] ...grown by this per second since that pose");
    MRPT_SAVE_CONFIG_VAR_COMMENT(local_yaw_deg, "[deg] half width of the local yaw interval (180: any)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(verify_hypotheses, "best hypotheses verified by fine registration");
    MRPT_SAVE_CONFIG_VAR_COMMENT(hypothesis_features, "a hypothesis's voxel-map solve: every k-th feature, at most this many (0: all)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(accept_inlier_ratio, "[-] inlier ratio a verified pose needs without a reference");
    MRPT_SAVE_CONFIG_VAR_COMMENT(ambiguity_ratio, "[-] another verified pose this x as good: ambiguous");
    MRPT_SAVE_CONFIG_VAR_COMMENT(distinct_xyz, "[m] verified poses farther apart are distinct");
    MRPT_SAVE_CONFIG_VAR_COMMENT(distinct_deg, "[deg] ...or rotated more than this");
    MRPT_SAVE_CONFIG_VAR_COMMENT(doubt_max_xyz, "[m] a frame in doubt takes a verified pose only within this");
    MRPT_SAVE_CONFIG_VAR_COMMENT(doubt_max_deg, "[deg] ...and within this rotation");
    MRPT_SAVE_CONFIG_VAR_COMMENT(doubt_search_period, "[s] a frame only in doubt is searched at most once per this (0: every one)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(out_of_map, "initial pose outside the map: error | global");
    MRPT_SAVE_CONFIG_VAR_COMMENT(start_xyz, "[m] a given initial pose's uncertainty: the first frame is also solved from seeds this far around it (0: off)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(start_deg, "[deg] ...and this far in yaw either way");
    MRPT_SAVE_CONFIG_VAR_COMMENT(start_ring_yaws, "the ring of seeds at the given yaw only (1: 8 seeds) or also turned either way (3: 20)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(start_refine_ratio, "[-] a seed's basin is refined by the frame's own registration when it fits >= this x the best one");
    MRPT_SAVE_CONFIG_VAR_COMMENT(start_distinct_xyz, "[m] start results farther apart are distinct places");
    MRPT_SAVE_CONFIG_VAR_COMMENT(start_distinct_deg, "[deg] ...or rotated more than this");
    MRPT_SAVE_CONFIG_VAR_COMMENT(track_candidates, "candidates of an ambiguous search tracked over the next scans (0: none)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(track_min_frames, "frames of evidence before a candidate is committed by its margin");
    MRPT_SAVE_CONFIG_VAR_COMMENT(track_ratio, "[-] commit when every other candidate's summed inliers <= this x the best's");
    MRPT_SAVE_CONFIG_VAR_COMMENT(track_consistent_frames, "...or the best was ahead of it on each of this many last frames");
    MRPT_SAVE_CONFIG_VAR_COMMENT(track_lead, "[-] ahead on a frame: the alternative's inliers under this x the best's");
    MRPT_SAVE_CONFIG_VAR_COMMENT(track_probe_xyz, "[m] a weak translation of the best is probed this far both ways");
    MRPT_SAVE_CONFIG_VAR_COMMENT(track_search_every, "a fresh search merged into the candidates every this many frames (0: when empty)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(track_max_frames, "frames a candidate set is tracked without a commit (then a fresh search)");
    MRPT_SAVE_CONFIG_VAR_COMMENT(track_max_ms, "[ms] per-frame budget for refining candidates");
}

bool RelocalizationParams::samePlace(const SE3d& a, const SE3d& b) const {
    return translationDistance(a, b) <= distinct_xyz && rotationAngle(a, b) <= distinct_deg * kDeg;
}

bool RelocalizationParams::sameStartBasin(const SE3d& a, const SE3d& b) const {
    return translationDistance(a, b) <= start_distinct_xyz && rotationAngle(a, b) <= start_distinct_deg * kDeg;
}

void RelocalizationParams::validate() const {
    if (local_after_lost < 1) throw ConfigError("[relocalization] local_after_lost must be >= 1");
    if (global_after_lost < local_after_lost)
        throw ConfigError("[relocalization] global_after_lost must be >= local_after_lost");
    if (!(local_radius > 0)) throw ConfigError("[relocalization] local_radius must be > 0");
    if (!(local_radius_rate >= 0)) throw ConfigError("[relocalization] local_radius_rate must be >= 0");
    if (!(local_yaw_deg > 0 && local_yaw_deg <= 180))
        throw ConfigError("[relocalization] local_yaw_deg must be in (0, 180]");
    if (verify_hypotheses < 1) throw ConfigError("[relocalization] verify_hypotheses must be >= 1");
    if (hypothesis_features < 0) throw ConfigError("[relocalization] hypothesis_features must be >= 0 (0: all)");
    if (!(accept_inlier_ratio > 0 && accept_inlier_ratio <= 1))
        throw ConfigError("[relocalization] accept_inlier_ratio must be in (0, 1]");
    if (!(ambiguity_ratio > 0 && ambiguity_ratio <= 1))
        throw ConfigError("[relocalization] ambiguity_ratio must be in (0, 1]");
    if (!(distinct_xyz > 0) || !(distinct_deg > 0))
        throw ConfigError("[relocalization] distinct_xyz and distinct_deg must be > 0");
    if (!(doubt_max_xyz > 0) || !(doubt_max_deg > 0))
        throw ConfigError("[relocalization] doubt_max_xyz and doubt_max_deg must be > 0");
    if (!(doubt_search_period >= 0) || !std::isfinite(doubt_search_period))
        throw ConfigError("[relocalization] doubt_search_period must be >= 0 s");
    if (out_of_map != "error" && out_of_map != "global")
        throw ConfigError("[relocalization] out_of_map = '" + out_of_map + "' (use error or global)");
    if (!(start_xyz >= 0) || !(start_deg >= 0) || start_deg > 180)
        throw ConfigError("[relocalization] start_xyz must be >= 0 and start_deg in [0, 180]");
    if (start_ring_yaws != 1 && start_ring_yaws != 3) throw ConfigError("[relocalization] start_ring_yaws must be 1 or 3");
    if (!(start_refine_ratio >= 0 && start_refine_ratio <= 1))
        throw ConfigError("[relocalization] start_refine_ratio must be in [0, 1]");
    if (!(start_distinct_xyz > 0) || !(start_distinct_deg > 0))
        throw ConfigError("[relocalization] start_distinct_xyz and start_distinct_deg must be > 0");
    if (track_candidates < 0) throw ConfigError("[relocalization] track_candidates must be >= 0");
    if (track_min_frames < 2) throw ConfigError("[relocalization] track_min_frames must be >= 2");
    if (!(track_ratio > 0 && track_ratio <= 1)) throw ConfigError("[relocalization] track_ratio must be in (0, 1]");
    if (track_consistent_frames < 2) throw ConfigError("[relocalization] track_consistent_frames must be >= 2");
    if (!(track_lead > 0 && track_lead <= 1)) throw ConfigError("[relocalization] track_lead must be in (0, 1]");
    if (!(track_probe_xyz > 0)) throw ConfigError("[relocalization] track_probe_xyz must be > 0");
    if (track_search_every < 0) throw ConfigError("[relocalization] track_search_every must be >= 0");
    if (track_max_frames < track_min_frames)
        throw ConfigError("[relocalization] track_max_frames must be >= track_min_frames");
    if (!(track_max_ms > 0)) throw ConfigError("[relocalization] track_max_ms must be > 0");
}

}  // namespace superloc::localization
