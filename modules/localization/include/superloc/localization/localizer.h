// The Localizer: per-frame scan-to-map pipeline with IMU (DESIGN §4) and its state.
//
//   1. predict the pose at scan time (IMU preintegration, or constant velocity without IMU)
//   2. deskew, filter, voxel-select and cap the features
//   3. associate with the PriorMap at the predicted pose
//   4. alignment risk of those correspondences (reported, and weighting the active prior)
//   5. solve (Ceres: scan + IMU + prior factors), re-associate, repeat
//   6. emit a FrameReport
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/system/COutputLogger.h>
#include <superloc/features/deskew.h>
#include <superloc/features/features_params.h>
#include <superloc/features/voxel_selector.h>
#include <superloc/fusion/estimate_information.h>
#include <superloc/fusion/frame_problem.h>
#include <superloc/fusion/fusion_params.h>
#include <superloc/imu/imu_params.h>
#include <superloc/localization/association.h>
#include <superloc/localization/frame_fusion.h>
#include <superloc/localization/frame_report.h>
#include <superloc/localization/icp_registration.h>
#include <superloc/localization/ndt_registration.h>
#include <superloc/localization/health.h>
#include <superloc/localization/localization_params.h>
#include <superloc/localization/localizer_params.h>
#include <superloc/localization/method_variant.h>
#include <superloc/localization/motion_model.h>
#include <superloc/localization/relocalization.h>
#include <superloc/localization/scan_features.h>
#include <superloc/localization/sensor_history.h>
#include <superloc/map/prior_map.h>
#include <superloc/reloc/global_search.h>
#include <superloc/risk/alignment_risk.h>

#include <memory>
#include <optional>
#include <vector>

namespace superloc::localization {

class NdtAligner;

/// A prior map with what the Localizer builds on it: the NDT grid (method ndt) and the global
/// search ([relocalization] enabled). Localizer::prepareMap makes one, e.g. in another thread
/// while frames go on; Localizer::setMap swaps it in between frames.
struct PreparedMap {
    std::shared_ptr<const map::PriorMap> map;
    std::unique_ptr<NdtAligner> ndt;
    std::unique_ptr<reloc::GlobalSearch> search;
    PreparedMap();
    PreparedMap(PreparedMap&&) noexcept;
    PreparedMap& operator=(PreparedMap&&) noexcept;
    ~PreparedMap();
};

class Localizer : public mrpt::system::COutputLogger {
   public:
    /// Throws ConfigError for a method that is not available yet.
    Localizer(const LocalizerParams& params, std::shared_ptr<const map::PriorMap> map);
    ~Localizer() override;

    /// Pose of the LiDAR at the first scan (T_map_lidar). Without it the first scan starts at
    /// the identity.
    void setInitialPose(const SE3d& T_map_lidar);
    /// The next scan is localized without a pose (doc/health.md): by the global search in the
    /// whole map, or in `region` when given, each hypothesis verified by the fine registration
    /// and the health checks. A scan that finds no unambiguous pose is reported lost and the
    /// next one tries again. For `--initial-pose auto`, a kidnap signalled from outside, or a
    /// "relocalize" service of a ROS node. Throws ConfigError when relocalization is disabled.
    void relocalize(const std::optional<reloc::SearchRegion>& region = std::nullopt);
    /// The global search over the map (built at construction when [relocalization] enabled).
    const reloc::GlobalSearch* globalSearch() const { return search_.get(); }
    /// Builds what `params` need on `map` (thread-safe: touches no Localizer). Throws
    /// ConfigError for an empty map.
    static PreparedMap prepareMap(const LocalizerParams& params, std::shared_ptr<const map::PriorMap> map);
    /// Replaces the prior map between frames (the tiles around the robot of a map::TiledMap):
    /// the next frames associate with the new map, its NDT grid and global search. The
    /// tracking state (pose, velocity, IMU, health) carries over. `prepared` must come from
    /// prepareMap with this Localizer's parameters.
    void setMap(PreparedMap&& prepared);
    /// prepareMap(params, map), then setMap.
    void setMap(std::shared_ptr<const map::PriorMap> map);
    /// Samples must come in time order, before the scans they precede.
    void addImu(const ImuSample& s);
    /// Second odometry (odom_alt) poses, kept for the relative-pose prior.
    void addOdomAlt(const PoseStamped& p);

    /// Runs the pipeline on one scan; never throws for bad data (see FrameReport::diverged).
    FrameReport process(const Scan& scan);

    /// For the localized map output, called right after process(scan) with the same scan: its
    /// valid points, one per `voxel` [m], deskewed, in the map frame at the estimate. Kept out
    /// of process() so that the frame's time is the localization's alone.
    const std::vector<Vec3f>& mapPoints(const Scan& scan, double voxel);
    /// For the observability scan (paper Fig. 4), called after process(): the last frame's
    /// correspondence points in the map frame at the estimate, with their translation label
    /// (0 x, 1 y, 2 z, risk::kNoLabel) from the risk rule at that pose. Outside the frame timing.
    void observabilityPoints(std::vector<Vec3f>& points, std::vector<int8_t>& labels) const;
    const LocalizerParams& params() const { return params_; }
    Method method() const { return method_; }

   private:
    struct Candidate;
    /// Steps 3-5 from the current state's pose; `wide`: first-frame search radius and rounds.
    /// What a solve is for. Track: this frame in the prior map. Hypothesis: verifying a pose of
    /// the global search (voxel association whatever the tracking one, no odom_alt prior, no
    /// eigen_remap). LastScan: the motion since the last frame, against its scan
    /// (motionFromLastScan; the tracking association, no odom_alt prior, no IMU window).
    enum class Solve { Track, Hypothesis, LastScan };
    void solveIcp(const imu::Preintegration* pre, bool wide, FrameReport& rep, Solve kind = Solve::Track);
    /// Unknown velocity without IMU (LocalizationParams::motion_from_last_scan): this frame's
    /// features registered, wide and from no motion, against the last frame's scan. When that
    /// converges with enough inliers, `pred` becomes the pose it measured and true is returned.
    /// The state, correspondences and statistics are left as they were.
    bool motionFromLastScan(Prediction& pred, FrameReport& rep);
    /// Unknown velocity with per-point times (LocalizationParams::sweep_velocity): the sweep's
    /// translation velocity, which deskew needs and nothing predicted, estimated with the pose
    /// from the converged frame's correspondences (a 9-DoF Gauss-Newton step), the features
    /// deskewed again with it and the frame re-solved as a tracked one, until it settles.
    void solveSweepVelocity(const Scan& scan, const Prediction& pred, const imu::Preintegration* pre,
                            FrameReport& rep);
    void solveNdt(const SE3d& T_imu_lidar, const imu::Preintegration* pre, FrameReport& rep);
    /// `unchecked`: no jump check against the prediction (unknown velocity, recovery).
    void finish(const Scan& scan, const Prediction& pred, bool unchecked, FrameReport& rep);
    /// What trying another pose for the current scan overwrites: the state, the correspondences,
    /// their statistics and the LiDAR pose. Saved before a verification, restored after.
    struct Solution {
        fusion::FrameState state;
        std::vector<Correspondence> corr;
        AssociationStats stats;
        SE3d T_map_lidar = SE3d::Identity();
    };
    Solution solution() const { return {cur_, corr_, last_stats_, last_T_map_lidar_}; }
    void restore(const Solution& s);
    /// A pose refined as the search's hypotheses are verified (localizer_relocalize.cpp): the
    /// state `start` at the scan's time, the fine registration from the voxel map's 1 m level
    /// without prior, inliers measured as tracking measures them, finished without a jump
    /// check, pred_dxyz / pred_ddeg against base.T_map_lidar_pred. `base` is the frame's report
    /// so far (its solve results are reset). Leaves the Solution at the refined pose.
    /// With kind = Track and `frame_pred` (the start check's seeds): the frame's own
    /// registration instead, as on a first frame, the sweep velocity estimated with the pose
    /// as the frame's own solve does (wantsSweepVelocity, from the prediction's sweep twist).
    FrameReport refineHypothesis(const Scan& scan, const fusion::FrameState& start, const FrameReport& base,
                                 Solve kind = Solve::Hypothesis, const Prediction* frame_pred = nullptr);
    /// A frame of unknown velocity estimates its sweep's translation velocity with its pose
    /// (LocalizationParams::sweep_velocity) when moving and deskewed.
    bool wantsSweepVelocity(const Prediction& pred) const;
    /// Relocalization on the current scan (localizer_relocalize.cpp): search (in `region`, or
    /// everywhere), verify the best hypotheses, commit the winner when it is unambiguous. On
    /// success rep and the state are the winner's (velocity unknown); else both stay as they
    /// were, with rep.reloc saying why.
    /// With `seeds` (the start check), the hypotheses are these poses instead of a search's, a
    /// rival must be start_distinct_* away, and the frame's own solve is one of the rivals.
    RelocOutcome runRelocalization(const Scan& scan, const Prediction& pred, const reloc::SearchRegion* region,
                                   FrameReport& rep, const std::vector<SE3d>* seeds = nullptr);
    /// The first frame from a given initial pose (localizer_start.cpp, doc/health.md "Start"):
    /// solved again from seeds around that pose within its uncertainty ([relocalization]
    /// start_xyz, start_deg); the best fit is taken, and a start that fits about as well
    /// elsewhere keeps its own solve, reported degraded (`start_ambiguous`).
    void verifyStart(const Scan& scan, const Prediction& pred, FrameReport& rep);
    /// The start check's seeds (localizer_start.cpp), each solved in the voxel map: one pose per
    /// basin they reach that fits within start_refine_ratio of the best, best first. Like
    /// refineHypothesis, it leaves the Solution at the last pose solved: save it before.
    std::vector<SE3d> startBasins(const Scan& scan, const std::vector<SE3d>& seeds, const FrameReport& rep);
    /// Multi-frame hypothesis tracking (doc/relocalization.md §4), first half: each kept
    /// candidate is moved by the measured motion since its frame, refined by the fine
    /// registration as a hypothesis, and its evidence accumulated; those lost or fitting clearly
    /// worse than the run's reference are dropped. The state is left as it was.
    void refineCandidates(const Scan& scan, FrameReport& rep);
    /// Second half, after this frame's search (if any) merged its hypotheses: the best candidate
    /// clearly and consistently best over the frames is committed (Accepted: rep and the state
    /// are its own); else the frame is reported lost with the best candidate's pose (Ambiguous),
    /// or Failed when no candidate is left.
    RelocOutcome decideCandidates(const Scan& scan, FrameReport& rep);
    /// Whether each translation the candidate's scan constrains weakly is held all the same:
    /// probes moved along it come back or fit clearly worse (localizer_candidates.cpp).
    bool weakAxesHeld(const Scan& scan, const Candidate& c);
    /// Where a frame lost `lost_run` frames in a row searches: around the last frame not lost
    /// (local), or nowhere in particular (global: empty).
    std::optional<reloc::SearchRegion> lostRegion(const Scan& scan, int lost_run) const;
    /// The health checks on the solved frame (its pose against the prediction first).
    void assess(FrameReport& rep);
    /// Step 7 (doc/health.md): a frame lost for a while, or in doubt, searches the map (when
    /// `may_search`), and the doubt carried to the next frames is updated.
    void recoverIfLost(const Scan& scan, const Prediction& pred, bool may_search, FrameReport& rep);
    /// What the next frame starts from: the last frame not lost, or (after a lost one) a
    /// restart from it at rest.
    void updateTrackingState(const Scan& scan, const Prediction& pred, const FrameReport& rep);

    LocalizerParams params_;
    Method method_;
    MethodVariant variant_;  ///< registration + odom_alt fusion policy of method_
    HealthMonitor health_;
    std::unique_ptr<reloc::GlobalSearch> search_;
    bool reloc_pending_ = false;                 ///< relocalize() was called: the next scan searches
    std::optional<reloc::SearchRegion> reloc_region_;
    int lost_run_ = 0;                           ///< consecutive lost frames
    /// The last frame not lost: where a local search looks, and where tracking restarts.
    struct GoodFrame {
        fusion::FrameState state;  ///< its state (time state.t)
        SE3d T_map_lidar;
    };
    std::optional<GoodFrame> last_good_;
    /// A pose of an ambiguous relocalization, tracked over the following scans (trackCandidates).
    struct Candidate {
        fusion::FrameState state;       ///< at its last frame (time state.t)
        bool has_velocity = false;      ///< state's velocity measured by the IMU over a tracked frame
        std::optional<SE3d> T_map_imu_before;  ///< its pose one frame earlier (constant velocity)
        double t_before = 0;
        double evidence = 0;            ///< summed inlier ratio over its frames
        int frames = 0;                 ///< frames of evidence (the search's included)
        std::vector<double> history;    ///< inlier ratio per frame, the latest last
        bool ruled_out = false;         ///< judged against the best on the last decision
        /// per translation axis: constrained by the scan (gamma >= weak_gamma) on one of its
        /// frames, every frame since moved by measured motion (IMU or odom_alt), which carries it
        std::array<bool, 3> axis_held{};
        FrameReport rep;                ///< its last frame's fit
        HealthChecks checks;            ///< ... and the health checks on it
        std::vector<Correspondence> corr;
        AssociationStats stats;
    };
    std::vector<Candidate> hypotheses_;  ///< the candidates being tracked (none: empty)
    std::string candidates_trigger_;  ///< the trigger of the search that gave the candidates
    int candidates_age_ = 0;          ///< frames the set has been tracked
    double track_ms_ = 0;             ///< [ms] refineCandidates() on this frame
    int track_dropped_ = 0, track_over_budget_ = 0;  ///< ...candidates it dropped, left out
    bool track_left_out_ = false;     ///< a hypothesis of this frame's search found the set full
    int track_judged_ = 0;            ///< candidates of this set dropped (lost, bad fit, ruled out)
    bool restart_ = false;     ///< the last frame was relocalized: velocity unknown
    /// every frame since the last `ok` one was predicted by the IMU (the doubt guard trusts it)
    bool imu_chain_ = true;
    bool doubt_ = false;       ///< a frame in doubt was not settled by a search: confirm the next
    /// the last frame was `ok` or a verified relocalization: its pose can anchor a velocity
    bool prev_verified_ = false;
    std::shared_ptr<const map::PriorMap> map_;
    std::unique_ptr<NdtAligner> ndt_;
    fusion::RobustKernel kernel_;
    Vec3d g_map_;

    SensorHistory sensors_;  ///< IMU and odom_alt between scans
    std::optional<SE3d> initial_T_map_lidar_;
    SE3d T_imu_lidar_ = SE3d::Identity();  ///< extrinsic of the scan being processed
    bool have_prev_ = false;
    fusion::FrameState prev_, cur_;
    std::optional<fusion::FrameState> prev_prev_;  ///< for the constant-velocity model
    /// The IMU window's prior on the previous state (FusionParams::window = marginalized): the
    /// marginal of the last frame's own solve, or none (fixed sigmas) when that frame's pose did
    /// not come from it. cur_marginal_: this frame's, from its last solve.
    std::optional<fusion::StatePrior> prev_marginal_, cur_marginal_;
    /// What the estimate knows without odom_alt (the weak-axis decision, doc/method.md §2); this
    /// frame's scan information above its noise floor (body), and where the estimate and the
    /// scan alone were weak.
    fusion::EstimateInformation est_info_;
    Mat6d scan_info_ = Mat6d::Zero();
    fusion::Weakness frame_est_, frame_scan_;
    size_t frames_ = 0;

    // Per-frame scratch (kept to avoid allocations in the hot path).
    Preprocessor preproc_;
    AssociationParams assoc_;  ///< the tracking association
    IcpRegistration icp_;
    NdtRegistration ndt_reg_;
    OdomAltLink odom_link_;
    ScanFeatures features_;  ///< the current scan's
    features::VoxelSelector map_selector_;
    SE3d last_T_map_lidar_ = SE3d::Identity();
    std::vector<uint32_t> map_idx_;
    std::vector<Vec3f> map_points_;
    /// The last frame's voxel candidates (deskewed, map frame at its pose) and its LiDAR
    /// position, kept without IMU for motionFromLastScan; empty after a lost frame.
    std::vector<Vec3f> last_scan_points_;
    Vec3f last_scan_origin_ = Vec3f::Zero();
    std::vector<Correspondence> corr_;
    AssociationStats last_stats_;
};

}  // namespace superloc::localization
