// Localizer parameters; section [localization] of the INI.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace superloc::localization {

/// doc/design.md#6-method-variants. `superloc`, `passive` and `eigen_remap` need the alignment-risk fusion.
enum class Method { Icp, Ndt, SuperLoc, Passive, EigenRemap, SuperLocPaper };
Method methodFromString(const std::string& s);  ///< throws ConfigError listing the names
const char* methodName(Method m);

struct LocalizationParams : public mrpt::config::CLoadableOptions {
    /// superloc | superloc_paper | icp | ndt | passive | eigen_remap (INI: its name; an unknown
    /// one is a ConfigError at load)
    Method method = Method::SuperLoc;
    bool use_imu = true;          ///< IMU prediction + factor when the rawlog has IMU samples
    std::string output_frame = "lidar";  ///< reported poses: lidar (T_map_lidar) or body (T_map_imu)

    // Association (paper §III-A, doc/localizer.md step 3): which one and its thresholds are
    // [association] (association_config.h); its reach, which the schedule and the covariance
    // also read, is here.
    /// [m] no correspondence beyond this: nearest map point (nearest; planes: at most twice the
    /// map's grid_cell), or voxel plane / line / centroid at the finest level, doubled per
    /// coarser level (voxel)
    double max_corr_dist = 1.0;
    double max_corr_dist_init = 3.0;   ///< [m] nearest, planes: the same, for the first rounds of a wide frame
    /// most association + solve rounds of a tracked frame (it stops earlier when settled)
    int rounds = 4;
    int rounds_init = 40;              ///< the same for a frame whose velocity is unknown
    /// [s] without IMU, a constant-velocity prediction over a longer gap counts as unknown
    /// velocity: the frame starts at the coarsest level and skips the jump check
    double max_cv_gap = 0.5;
    /// without IMU, a frame of unknown velocity after a tracked one is first registered against
    /// that frame's scan (wide, from no motion): the motion it measures is the prediction, and
    /// the frame is then solved in the map as a tracked one (doc/localizer.md, "Unknown velocity")
    bool motion_from_last_scan = true;
    /// [deg] that motion's first guess: the turn about the vertical, in steps of this, under
    /// which most of the frame's features find the last scan within 1 m (no turn unless one
    /// scores a fifth more); 0: from no motion only (doc/localizer.md, "Unknown velocity")
    double last_scan_yaw_step = 30;
    /// that registration uses every k-th feature, k chosen so that at most this many remain (the
    /// motion only has to land the map solve inside its basin, which then uses them all); 0: all
    int last_scan_features = 500;
    /// a frame of unknown velocity whose points carry times (deskew on) estimates the sweep's
    /// translation velocity with its pose, instead of deskewing by rotation alone
    bool sweep_velocity = true;
    double converged_xyz = 0.002;      ///< [m] stop re-associating when the update is below...
    double converged_deg = 0.02;       ///< [deg] ...both of these
    /// A tracked frame's round that moved the pose less than settle_xyz and settle_deg (at the
    /// finest resolution) ends the kernel's annealing: the next rounds run at its floor, where
    /// the last frame confirmed the motion prediction (doc/localizer.md step 5); 0: anneal every
    /// round down to the floor
    double settle_xyz = 0.05;          ///< [m]
    double settle_deg = 0.5;           ///< [deg]
    /// Without IMU, a frame whose motion was measured against the last scan may settle as above
    /// too, provided the last frame was tracked to a converged `ok` end and was neither the
    /// first frame nor a wide start (doc/localizer.md step 5); false: only frames whose motion
    /// prediction the last frame confirmed settle
    bool settle_after_scan = true;

    // Divergence detection (reported per frame, the run goes on)
    double inlier_dist = 0.2;          ///< [m] a feature is an inlier when its residual is below
    double min_inlier_ratio = 0.3;     ///< [-] below: diverged
    double max_jump_xyz = 1.0;         ///< [m] solved vs predicted pose farther: diverged
    double max_jump_deg = 10.0;        ///< [deg] idem for the rotation

    // method = ndt (PCL NormalDistributionsTransform as the registration step)
    double ndt_resolution = 1.0;       ///< [m] NDT cell size
    double ndt_step_size = 0.1;        ///< [m] More-Thuente line-search max step
    double ndt_epsilon = 1e-4;         ///< [m] transformation epsilon (PCL 1.13 stops after one
                                       ///< 0.1 m step at hdl_localization's 0.01)
    int ndt_max_iterations = 30;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
    /// Throws ConfigError naming [localization] and the key when a value is out of range.
    void validate() const;
};

}  // namespace superloc::localization
