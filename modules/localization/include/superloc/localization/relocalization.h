// Relocalization (doc/health.md): what the Localizer does when it has no pose (`--initial-pose
// auto`) or has lost it. The global search (reloc::GlobalSearch) proposes poses; each is
// verified by the localizer's own fine registration from that pose and by the health checks;
// a winner is committed only when nothing else explains the scan about as well and no axis of
// it is unconstrained (the paper's alignment risk: a corridor's scan fits everywhere along it).
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <superloc/core/types.h>

#include <string>
#include <vector>

namespace superloc::localization {

/// Section [relocalization] of the INI.
struct RelocalizationParams : public mrpt::config::CLoadableOptions {
    bool enabled = true;          ///< search again when lost (every method alike); off: stay lost
    int local_after_lost = 1;     ///< consecutive lost frames before a search around the last pose
    int global_after_lost = 3;    ///< ...before a search in the whole map
    double local_radius = 5.0;    ///< [m] radius of the local search around the last tracked pose
    double local_radius_rate = 2.0;  ///< [m/s] grows by this per second since that pose
    double local_yaw_deg = 180;   ///< [deg] half width of its yaw interval (180: any yaw)
    int verify_hypotheses = 3;    ///< best hypotheses verified by fine registration
    /// a hypothesis's voxel-map solve (a search's, a start seed's) uses every k-th feature, at
    /// most this many (0: all); a search's is then polished and measured on them all, a start
    /// seed's measured on these alone. Off by default: 500 made KITTI's warped map 4x faster but
    /// put KITTI's split frames 0.11-0.19 m off where four tests ask 0.1 (doc/health.md)
    int hypothesis_features = 0;
    /// [-] with no reference inlier ratio yet (initial pose auto): a verified pose needs this
    double accept_inlier_ratio = 0.35;
    /// [-] a second verified pose elsewhere with at least this x the winner's inlier ratio: ambiguous
    double ambiguity_ratio = 0.9;
    double distinct_xyz = 2.0;    ///< [m] verified poses farther apart than this are distinct...
    double distinct_deg = 20.0;   ///< [deg] ...or rotated more than this
    /// a frame searched because it was in doubt (not lost), with an IMU prediction, takes a verified pose only within
    /// this of its own solve: a correction, not a move to another place
    double doubt_max_xyz = 1.5;   ///< [m]
    double doubt_max_deg = 15.0;  ///< [deg]
    /// [s] after a doubt's search confirmed the frame's own pose (not_better), a frame only in
    /// doubt (it did not settle in its rounds, or waits for a search to confirm it; not one that
    /// fits clearly worse, nor a lost one) within this period is not searched: it keeps its own
    /// pose, degraded, its doubt carried to the next frame (frames.csv reloc_result `deferred`). Bounds what a map that disagrees with the scans
    /// costs (KITTI's warped map: a search, 65-85 ms, on 4 of 7 tracked frames), at the price of
    /// frames left off until the next search (doc/health.md). 0 (default): every such frame.
    double doubt_search_period = 0.0;
    /// an initial pose outside the map's bounds (grown by features.max_range): `error` (one-line
    /// error) or `global` (localize the first scan globally instead)
    std::string out_of_map = "error";
    /// The uncertainty of a given initial pose (doc/health.md, "Start"): the first frame is also
    /// solved from seeds this far around it (a ring in the horizontal plane, and the yaw either
    /// way), and the best-fitting result is taken; one that fits about as well elsewhere makes
    /// the start ambiguous. 0: the given pose is trusted as it is.
    double start_xyz = 1.5;  ///< [m]
    double start_deg = 15;   ///< [deg]
    /// the ring's seeds at the given yaw only (1: 8 seeds) or also turned either way (3: 20)
    int start_ring_yaws = 3;
    /// [-] a seed's basin is solved by the frame's own registration only when its voxel-map
    /// solve fits at least this x the best basin's inlier ratio
    double start_refine_ratio = 0.7;
    /// [m] / [deg] start results farther apart than this are distinct places (rivals)
    double start_distinct_xyz = 0.3;
    double start_distinct_deg = 3.0;
    /// Multi-frame hypothesis tracking (doc/relocalization.md §4): an ambiguous relocalization
    /// of a frame without a pose keeps up to this many candidates and tracks each over the next
    /// scans, accumulating evidence, until one is clearly best; 0: none kept (each scan searches
    /// afresh)
    int track_candidates = 10;
    /// frames of evidence (the search's included) before a candidate may be committed by its margin
    int track_min_frames = 4;
    /// [-] commit when every other surviving candidate's summed inlier ratio is at most this x
    /// the best's (or the best is the only survivor); the best must fit healthily on the frame
    double track_ratio = 0.9;
    /// an alternative is also ruled out when the best was ahead of it on each of its last this
    /// many frames tracked together (consistently best)
    int track_consistent_frames = 4;
    /// [-] ahead on a frame: the alternative's inlier ratio under this x the best's (not a tie)
    double track_lead = 1.0;
    /// [m] a weak translation of the best candidate is probed this far both ways before a commit
    double track_probe_xyz = 1.0;
    /// a fresh search every this many tracked frames, its hypotheses merged into the set as
    /// candidates (0: only when the set is empty)
    int track_search_every = 1;
    /// frames a candidate set is tracked without a commit before it is dropped (a fresh search)
    int track_max_frames = 20;
    /// [ms] refinement budget per frame: candidates not refined within it are dropped (worst first)
    double track_max_ms = 1000;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    void validate() const;
    /// Two poses within distinct_xyz and distinct_deg of each other: one place, not two.
    bool samePlace(const SE3d& a, const SE3d& b) const;
    /// Two start results within start_distinct_xyz and start_distinct_deg: one basin.
    bool sameStartBasin(const SE3d& a, const SE3d& b) const;
};

/// How a relocalization ended.
enum class RelocOutcome {
    None,       ///< none ran on this frame
    Accepted,   ///< a verified, unambiguous pose replaced the frame's own
    NotBetter,  ///< nothing verified fits better than the frame's own solve: it stands (confirmed)
    TooFar,     ///< a frame in doubt (IMU-predicted) would have moved too far: not taken
    Ambiguous,  ///< distinct verified poses fit about as well, or the winner has a weak axis
    Failed,     ///< no hypothesis, or none verified
    Deferred    ///< a frame in doubt not searched: one was, less than doubt_search_period ago
};
/// "", "accepted", "not_better", "too_far", "ambiguous", "failed", "deferred" (frames.csv
/// reloc_result).
const char* relocOutcomeName(RelocOutcome o);

/// What a relocalization did on a frame (FrameReport::reloc).
struct RelocReport {
    /// "" none, "local" (around the last pose), "global" (whole map), "track" (the candidates of
    /// an earlier ambiguous search refined on this scan)
    std::string mode;
    std::string trigger;  ///< "request" (relocalize()), "lost", "doubt" (degraded, in doubt)
    RelocOutcome outcome = RelocOutcome::None;
    std::string detail;   ///< why: "no_hypothesis: ...", "verification", "alternatives+weak_x", ...
    int hypotheses = 0;   ///< proposed by the search
    int verified = 0;     ///< passed the fine registration and health checks
    double search_ms = 0; ///< [ms] global search
    double verify_ms = 0; ///< [ms] fine registrations of the hypotheses
    std::vector<SE3d> alternatives;  ///< T_map_lidar of the other verified poses (ambiguous)
    /// candidates tracked after this frame (mode "track", or an ambiguous search that kept them)
    int candidates = 0;
    /// [-] runner-up candidate's summed evidence / the best's (0: none or one candidate)
    double evidence_ratio = 0;
};

}  // namespace superloc::localization
