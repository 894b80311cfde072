// The Tracker (doc/localizer.md "Structure"): one frame from its prediction to its solution, and
// what the next frame starts from.
//   begin     step 1 motion model (motion_model.h), step 2 features (scan_features.h), into Frame
//             (its report too)
//   track     steps 3-6: the method's registration (registration.h) with the IMU window and the
//             odom_alt fusion (frame_fusion.h), the sweep velocity of a frame of unknown
//             velocity, then the frame's quality, divergence and velocity (finish)
//   solveFrom the same registration from another start (a pose the Recovery verifies)
//   end       the frame's final state becomes the next frame's previous one, with its marginal,
//             its estimate information and the last scan (motion of the next frame without IMU)
// Every solve returns a FrameSolution by value, its report (TrackReport) included; the Tracker's
// own state changes in end() only.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <cmath>
#include <superloc/localization/frame_fusion.h>
#include <superloc/localization/icp_registration.h>
#include <superloc/localization/localizer_params.h>
#include <superloc/localization/method_variant.h>
#include <superloc/localization/motion_model.h>
#include <superloc/localization/ndt_registration.h>
#include <superloc/localization/registration.h>
#include <superloc/localization/scan_features.h>
#include <superloc/localization/sensor_history.h>

#include <memory>
#include <optional>
#include <vector>

namespace superloc::localization {

/// The frame being processed: its scan, prediction and features, and the IMU window's previous
/// state as this frame's own solves leave it (optimised with the current state when the IMU
/// takes part).
struct Frame {
    const Scan* scan = nullptr;
    bool first = false;             ///< no frame before it was placed (no previous state)
    Prediction pred;
    imu::Preintegration pre;        ///< the prediction's preintegration (pred.used_imu)
    fusion::FrameState start;       ///< the predicted state at the scan's time: where solves start
    fusion::FrameState prev;        ///< the previous frame's state (the IMU window's first)
    ScanFeatures features;          ///< step 2 (deskewed again by the sweep velocity)
    /// What steps 1-2 gave (prediction, feature counts, their times): every solve of the frame
    /// starts its own report from it.
    TrackReport report;
};

/// How a pose is verified: as a hypothesis (voxel map, from its 1 m level, no prior; its fit
/// measured on every feature as tracking measures it), as a start seed (solved as a hypothesis,
/// its fit measured on its solve's own voxel-map correspondences, on [relocalization]
/// hypothesis_features where set: only its basin is wanted, and the seeds are compared with each
/// other), or as the first frame's own registration (a start basin, with its sweep velocity).
enum class VerifyAs { Hypothesis, Seed, FirstFrame };

class Tracker {
   public:
    Tracker(const LocalizerParams& params, const MethodVariant& variant, const SensorHistory& sensors,
            const mrpt::system::COutputLogger& log);
    /// The prior map (and its NDT grid, method ndt) the next frames are solved in.
    void setMap(std::shared_ptr<const map::PriorMap> map, const NdtAligner* ndt);
    /// The method's registration (MethodVariant::registration): what every tracked solve uses.
    const Registration& registration() const { return *reg_; }
    const map::PriorMap& map() const { return *map_; }

    /// A frame was placed (the next one is not a first frame).
    bool started() const { return have_prev_; }
    /// Steps 1-2: the prediction (a first frame at `T_map_lidar0`) and the features.
    void begin(const Scan& scan, const SE3d& T_map_lidar0, Frame& f);
    /// Whether the frame's velocity is unknown (doc/localizer.md "Unknown velocity": a first
    /// frame, a restart, no IMU and no velocity yet or a gap over max_cv_gap). Without IMU, when
    /// `may_measure`, the motion measured against the last scan makes it known: the prediction
    /// becomes that motion (f.report.motion_from_scan).
    bool velocityUnknown(Frame& f, bool may_measure);
    /// Steps 3-6: the frame's own solve from its prediction; `velocity_unknown`: wide, from the
    /// coarsest level, no jump check. Its report starts from f.report.
    FrameSolution track(Frame& f, bool velocity_unknown);
    /// The frame solved again from `start` (at the scan's time), wide and with no jump check,
    /// finished as the frame would be; its report is `base` (the report it builds on) with the
    /// solve's fields. A hypothesis is solved in the voxel map without prior, its inliers
    /// measured as tracking measures them; a start seed (VerifyAs::FirstFrame) as the frame's own
    /// ICP solve is, without IMU, with its sweep velocity (which deskews f's features again, as
    /// track does). Both by ICP whatever the method (ndt's start seeds too).
    FrameSolution solveFrom(Frame& f, const fusion::FrameState& start, VerifyAs as, const TrackReport& base);
    /// The frame is final at `state` (its solution's, or a restart's): what the next frame starts
    /// from. `sol`: the frame's final solution (marginal, fusion evidence); `requested`: the
    /// frame was localized without a pose; `pending`: a relocalization is still asked for;
    /// `restart`: the next frame starts with its velocity unknown (a relocalization, a restart
    /// from the last frame not lost: Recovery::endFrame).
    void end(const Frame& f, const fusion::FrameState& state, const FrameSolution& sol, const FrameReport& rep,
             bool requested, bool pending, bool restart);
    /// A frame whose own registration is in doubt (not converged, or fitting clearly worse than
    /// the map gives: health's checks) keeps what it knew without its scan: `sol`'s posterior
    /// becomes that (what end() carries on), and its covariance, as posterior() reports it, is
    /// returned (doc/method.md §4).
    Mat6d dropScan(FrameSolution& sol) const;
    /// The frame's correspondences back once nothing needs them: the next track() solves into
    /// them (no allocation per frame).
    void recycle(std::vector<Correspondence>&& corr) { spare_corr_ = std::move(corr); }

   private:
    /// A solve of f's features in the map in use from f's window: a tracked one (purpose Track)
    /// with the IMU window's prior and marginal, `imu` when the frame has it.
    RegistrationProblem problem(Frame& f, SolvePurpose purpose, bool wide, const imu::Preintegration* imu) const;
    /// The IMU window and odom_alt fusion's solve (SolvePurpose::Track) of `sol` from its state,
    /// by `reg`; `may_settle`: RegistrationProblem::may_settle (the frame's own solve only).
    void trackedSolve(const Registration& reg, Frame& f, FrameSolution& sol, bool wide, const imu::Preintegration* imu,
                      bool may_settle = false);
    /// Without IMU (unknown_velocity.cpp): f's features registered, wide and from no motion,
    /// against the last frame's scan; when that converges with enough inliers, the prediction
    /// becomes the motion it measured and true is returned (its times in f.report).
    bool measureMotion(Frame& f);
    /// With timed points (unknown_velocity.cpp): the sweep's translation velocity, estimated with
    /// the pose from the converged solve's correspondences (a 9-DoF Gauss-Newton step), the
    /// features deskewed again with it and the frame re-solved as a tracked one, until it settles.
    void sweepVelocity(Frame& f, const Prediction& pred, const imu::Preintegration* imu, FrameSolution& sol);
    bool wantsSweepVelocity(const Prediction& pred) const;
    /// Step 6: the quality at the estimate, divergence (`unchecked`: no jump check against the
    /// prediction), the velocity without IMU, the reported poses.
    /// `features`: those the solve's correspondences come from (default: the frame's).
    void finish(const Frame& f, const Prediction& pred, bool unchecked, FrameSolution& sol,
                const ScanFeatures* features = nullptr) const;

    LocalizerParams params_;
    const MethodVariant& variant_;
    const SensorHistory& sensors_;
    const mrpt::system::COutputLogger& log_;
    Vec3d g_map_;
    Preprocessor preproc_;
    IcpRegistration icp_;
    NdtRegistration ndt_;
    const Registration* reg_;  ///< icp_ or ndt_, by the method
    OdomAltLink odom_link_;
    std::shared_ptr<const map::PriorMap> map_;

    // What the next frame starts from.
    bool have_prev_ = false;
    bool restart_ = false;  ///< the last frame was relocalized or restarted: velocity unknown
    /// The last frame was tracked from its motion prediction (not the last scan's, not wide),
    /// converged, `ok`, and ended within settle_xyz / settle_deg of the prediction: the next
    /// frame's solve may settle (RegistrationProblem::may_settle)
    bool prediction_confirmed_ = false;
    /// The last frame was tracked to a converged, `ok` end, not the first and not a wide start
    /// (its prediction need not have been confirmed): with settle_after_scan the next frame's
    /// solve may settle
    bool last_sound_ = false;
    /// The last frame, tracked, was weak in translation (a translation gamma below [association]
    /// points_below_gamma): the next starts without voxel planes
    /// (RegistrationProblem::without_voxel_planes)
    bool last_weak_ = false;
    fusion::FrameState prev_;
    std::optional<fusion::FrameState> prev_prev_;  ///< for the constant-velocity model
    /// The IMU window's prior on the previous state (FusionParams::window = marginalized): the
    /// marginal of the last frame's own solve, or none (fixed sigmas) when that frame's pose did
    /// not come from it.
    std::optional<fusion::StatePrior> prev_marginal_;
    /// What the estimate knows without odom_alt (the weak-axis decision, doc/method.md §2).
    fusion::EstimateInformation est_info_{std::pow(std::sin(params_.risk.normal_noise_deg * M_PI / 180), 2),
                                          params_.risk.weak_sigma_xyz};
    /// The estimate's and the pose covariance's IMU window from `prev` to `cur` (copies): the
    /// IMU chain at estimate_imu_scale of [imu]'s noise (`imu` null: none).
    struct EstimateWindow {
        EstimateWindow(const fusion::FrameState& prev, const fusion::FrameState& cur, const imu::Preintegration* imu,
                       const LocalizerParams& params);
        EstimateWindow(const EstimateWindow&) = delete;
        EstimateWindow& operator=(const EstimateWindow&) = delete;
        fusion::FrameState pv, c;
        std::optional<imu::Preintegration> est_imu;
        fusion::FrameProblemInputs in;
    };
    /// The reported pose's covariance (doc/method.md §4): scan, IMU window and odom_alt together.
    fusion::PosePosterior post_;
    /// [s] since when a weak axis held by nothing measured has had the pose's position std
    /// above [health] max_sigma_xyz (the stretch's first such frame)
    std::optional<double> blind_since_;
    /// The frame's posterior (tracked frames), from its solve: what the IMU chain, odom_alt's
    /// prior and the scan give the solved state.
    void posterior(const Frame& f, FrameSolution& sol) const;
    /// How the sensor's path departed from the one the sweep was deskewed along; none where it
    /// was deskewed along the IMU or is untimed.
    fusion::SweepDeparture sweepDeparture(const Frame& f, const fusion::FrameState& cur) const;
    /// The covariance that departure leaves in the solved pose, through the scan's geometry and
    /// its points' times (added to the posterior's; doc/method.md §4).
    Mat6d sweepCovariance(const Frame& f, const FrameSolution& sol) const;
    /// The frame's sweep was deskewed along the IMU's trajectory (the position's floor is then
    /// the map's alone, [fusion] cov_floor_imu_xyz).
    static bool deskewedAlongImu(const Frame& f);
    /// A solve without the filter (a hypothesis, ndt, a diverged frame): the covariance of its
    /// scan alone, above its noise floor (doc/method.md §4).
    void scanCovariance(FrameSolution& sol) const;
    /// The last frame's voxel candidates (deskewed, map frame at its pose) and its LiDAR
    /// position, kept without IMU for measureMotion; empty after a lost frame.
    std::vector<Vec3f> last_scan_points_;
    Vec3f last_scan_origin_ = Vec3f::Zero();
    std::vector<Correspondence> spare_corr_;  ///< recycle()
};

}  // namespace superloc::localization
