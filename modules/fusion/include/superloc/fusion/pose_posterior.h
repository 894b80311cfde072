// The covariance of the pose a frame reports (doc/method.md §4): what the frame's solve knows of
// it, the scan, the IMU window and odom_alt's prior together, made consistent with the error it
// really makes.
//
// A recursive information filter beside the solver, like EstimateInformation but with everything
// the solve has: each frame, the last frame's information is carried to the current state
// through the IMU factor *and* odom_alt's relative prior (without IMU, the pose alone through
// the prior), and the scan's information is added. Three differences from the solver's own
// marginal make it consistent:
//   - the IMU chain at the noise it really has (ActiveFusionParams::estimate_imu_scale), not
//     the solver's inflated [imu] densities;
//   - odom_alt's prior with the information it has shown (OdomFusionActive: out of sample), not
//     the solver's scale of it; the passive prior as the method uses it;
//   - the scan's information above its noise floor (informationAboveNoise): noisy wall normals do
//     not hold a corridor's axis;
// and the covariance gets a floor `floor` (6 stds, body axes) for the errors every residual of
// a frame shares and no count of residuals reveals (the map's own error, the sweep's deskew and
// timing): measured on the simulated worlds and the real splits (doc/method.md §4).
//
// Coordinates: a right perturbation of T_map_imu, T Exp(d), d = (translation in body axes,
// rotation vector), as scanInformation; toReported() turns it into the reported pose's ROS
// convention.
#pragma once

#include <superloc/core/correspondence.h>
#include <superloc/core/types.h>
#include <superloc/fusion/frame_problem.h>
#include <superloc/fusion/state_prior_factor.h>

#include <optional>
#include <utility>
#include <vector>

namespace superloc::fusion {

/// The std a map error of `map_sigma` [m], coherent over the scan's footprint, leaves in the
/// rotation about each body axis [rad]: map_sigma / r_k, with r_k = sqrt(3 H(3+k,3+k) / tr H_tt)
/// the scan's lever arm about axis k read off its information `H` (for point-to-plane residuals
/// H_tt sums n n^T and H_rr (p x n)(p x n)^T, so r_k is the RMS torque arm about k). Zero where
/// `H` holds no translation or no rotation about k (nothing to scale), or map_sigma is 0.
Vec3d mapRotationFloor(const Mat6d& H, double map_sigma);

/// The map's error as a pose solved from `corr` at T_map_imu takes it (doc/method.md §4, "The
/// map's error in the position"): the prior map is off by a smooth random displacement field,
/// per-axis std 1 and correlation exp(-d^2 / 2 length^2) between points d apart; a residual moves
/// by the field at its map point projected on its normal, and the solve answers with
/// dt = H^-1 sum_i h_i delta(q_i), h_i the correspondence's translation information (plane:
/// n n^T, line: I - n n^T, point: I; times its weight), H = sum_i h_i. Its covariance is
/// M = H^-1 (sum_ij rho_ij h_i h_j) H^-1, summed over cells of `cell` metres (coarser, by
/// doubling, where the scan spans more than kMapShareMaxCells of them): a field coherent over the
/// whole footprint (length -> inf) gives M = I, one that decorrelates within it averages out.
/// Eigenvalues clamped to [0, 1]; directions the scan does not hold above its noise floor
/// (`floor_share` of the trace, as informationAboveNoise) take the whole field (1). Body axes
/// (3 x 3, translation). Identity where there is nothing to read it off.
Mat3d mapErrorShare(const std::vector<Correspondence>& corr, const SE3d& T_map_imu, double cell, double length,
                    double floor_share);
/// mapErrorShare's cap on the cells it sums pairs over (a pair costs a 3 x 3 product).
constexpr int kMapShareMaxCells = 64;

/// What a frame's covariance floor is read off (PosePosterior::covariance).
struct FloorGeometry {
    FloorGeometry() = default;
    explicit FloorGeometry(const Mat6d& H_, bool imu_deskewed_ = false, std::optional<Mat3d> map_share_ = std::nullopt)
        : H(H_), imu_deskewed(imu_deskewed_), map_share(std::move(map_share_)) {}
    /// The scan's information above its noise floor: the rotation floor's lever arms.
    Mat6d H = Mat6d::Zero();
    /// The sweep was deskewed along the IMU's trajectory: the position's floor is the map's alone.
    bool imu_deskewed = false;
    /// The share of the map's error the position takes (body axes, mapErrorShare); empty: all
    /// of it on every axis (the constant floor).
    std::optional<Mat3d> map_share;
};

/// What PosePosterior::update needs to leave the scan out along a direction carried beyond the
/// association's reach (beyondReach; doc/method.md §4, "Beyond the association's reach").
struct ScanReach {
    Vec6d gamma = Vec6d::Ones();  ///< the frame's risk per body axis
    double weak_gamma = 0.3;      ///< [-] below: the scan does not hold the axis
    double reach = 1.0 / 3.0;     ///< [m] the carried std beyond which the association may alias
};

/// What a carried position's drift puts across its own direction when that direction is known
/// to `tilt` [rad] only: the covariance `C`'s position block has its largest eigenvalue λ along
/// u; the direction the pose really drifts along may be tilted from u by `tilt`, which moves the
/// position across u by tilt x its displacement along u: tilt^2 λ (I - u u^T), added to the
/// position block. Along a direction the information leaves unheld (λ at kMaxSigma^2, a pose
/// not carried there at all), nothing: the linear picture says nothing of metres of tilt there.
Mat6d driftTiltCovariance(const Mat6d& C, double tilt);

class PosePosterior {
   public:
    /// `floor`: the std floor per axis (x y z [m], roll pitch yaw [rad]); `map_sigma` [m]: the
    /// map's coherent error, which raises the rotation's floor per frame (mapRotationFloor);
    /// `floor_xyz_imu` [m]: the position's floor of a frame whose sweep was deskewed along the
    /// IMU's trajectory (no deskew or timing error left to share: the map's error; negative:
    /// `floor`'s). Where a frame's FloorGeometry has a map share M, that much of the position's
    /// floor is the map's: floor_xyz_imu^2 M, and the rest of `floor` (deskew, timing) stays
    /// whole: (floor^2 - floor_xyz_imu^2) I.
    /// `drift_tilt` [rad]: how well the direction a carried position drifts along is known
    /// (driftTiltCovariance); 0: exactly.
    explicit PosePosterior(const Vec6d& floor = Vec6d::Zero(), double map_sigma = 0.0, double floor_xyz_imu = -1.0,
                           double drift_tilt = 0.0)
        : floor_(floor), map_sigma_(map_sigma), floor_xyz_imu_(floor_xyz_imu), drift_tilt_(drift_tilt) {}

    struct Update {
        /// The current state's information after the frame (IMU: 15 x 15; without: pose only,
        /// in the top-left 6 x 6), to commit.
        Mat15d info = Mat15d::Zero();
        bool with_imu = false;
        SE3d T_ref = SE3d::Identity();
        Vec9d sb_ref = Vec9d::Zero();
        Mat6d cov = Mat6d::Identity();  ///< the pose's covariance, floor included
        FloorGeometry floor;            ///< what `cov`'s floor was read off (for withoutScan)
        /// `info` without the frame's scan (the carried information alone), for withoutScan().
        Mat15d info_without_scan = Mat15d::Zero();
        /// The pose's part of info_without_scan (with IMU the velocity and biases marginalized).
        Mat6d carriedPoseInformation() const;
    };

    /// One frame: `in.prev`, `in.cur` (the solved state), `in.imu` (at the estimate's noise
    /// scale, or null), `in.prior` (odom_alt's prior at the information it is worth, or none),
    /// and the scan's information above its noise floor, of which the filter adds what the
    /// estimate does (`H_added`, EstimateInformation::scanPart); `floor`: what the covariance's
    /// floor is read off (its H: the scan's information above its noise floor, whole). Does
    /// not change the filter. With `reach`, the scan is not taken along the carried position's
    /// direction beyondReach names (its Schur complement along it, withoutDirection).
    Update update(const FrameProblemInputs& in, const FusionParams& params, const Mat6d& H_added,
                  const FloorGeometry& floor, const std::optional<ScanReach>& reach = std::nullopt) const;
    /// `u` without its frame's scan: what the frame knows when its registration is in doubt (not
    /// converged, or fitting clearly worse than this map gives), the scan's information being
    /// taken at associations that may be wrong (a corridor's end wall coming into view 5 m from
    /// where the drifted pose puts it: 1 cm claimed, 5.4 m off). Its `info` is what the frame
    /// then carries, its `cov` (the same floor as `u`'s) what it reports. Computed only for such
    /// a frame.
    Update withoutScan(const Update& u) const;
    /// The frame is final: its information is the next frame's prior.
    void commit(const Update& u);
    /// Forget everything (a lost, diverged or relocalized frame).
    void reset();
    /// A pose's covariance from its information alone, floor included (unheld directions capped
    /// at kMaxSigma); the rotation's floor raised to what the map's coherent error leaves at the
    /// lever arms of the scan information `floor.H` (mapRotationFloor); the position's floor
    /// shaped by the map share where `floor` has one; across the position's most uncertain
    /// direction, what that direction's tilt leaves (driftTiltCovariance).
    Mat6d covariance(const Mat6d& info, const FloorGeometry& floor) const;
    /// The floor's covariance of a frame (body axes).
    Mat6d floorCovariance(const FloorGeometry& floor) const;
    /// The std floor per body axis without a map share (the constant floor's stds).
    Vec6d floor(const FloorGeometry& floor) const;

   private:
    Vec6d floor_;
    double map_sigma_ = 0.0;
    double floor_xyz_imu_ = -1.0;
    double drift_tilt_ = 0.0;
    std::optional<StatePrior> prior_;  ///< with IMU: on the last committed state
    std::optional<std::pair<SE3d, Mat6d>> pose_prior_;  ///< without: T_map_imu and its information
};

/// How the sensor's path departed from the one a sweep was deskewed along (doc/method.md §4 "The
/// sweep"): a point at s in [0, 1] of the sweep (its first point to its last, the scan's time) was
/// placed g(s) delta off, delta (body axes: x y z [m], roll pitch yaw [rad]) at its largest, g a
/// parabola through both ends (4 s (1 - s): a constant acceleration off a constant twist) or
/// growing back from the scan's time (1 - s: a wrong rate, or no deskew); T [s] the sweep's span.
struct SweepDeparture {
    Vec6d delta = Vec6d::Zero();
    bool parabola = false;
    double T = 0;
    bool none() const { return delta.isZero() || !(T > 0); }
};

/// The covariance that departure leaves in a pose solved at T_map_imu from `corr` (each with its
/// point's time, Correspondence::rel_time) with `carried` the pose's information without the scan
/// (body axes, as scanInformation). A point at s is displaced by g(s) (delta_t + delta_r x p), so
/// its residual by g(s) J delta; the solve answers with M delta, M = (A + C)^-1 A_g, A the scan's
/// information above its noise floor (informationAboveNoise with `floor_share`), A_g the same with
/// each residual weighted by g. Each axis's departure independent with std |delta_k|:
/// M diag(delta^2) M^T. One g for every point gives M = g I; points that see a direction at
/// different times couple the axes (floor ahead and behind: z with pitch).
Mat6d sweepCovariance(const std::vector<Correspondence>& corr, const SE3d& T_map_imu, const SweepDeparture& d,
                      double scan_sigma, double floor_share, const Mat6d& carried);

/// The covariance `C` of a right perturbation of T_map_imu as the ROS convention of the reported
/// pose T_map_imu * T_imu_out (e.g. T_imu_lidar): position in the map frame, rotation about the
/// map's fixed axes, order (x y z rotX rotY rotZ) — geometry_msgs/PoseWithCovariance.
Mat6d toReported(const Mat6d& C, const SE3d& T_map_imu, const SE3d& T_imu_out);

/// The largest std of a 3 x 3 covariance block (its largest eigenvalue's root): the pose's std
/// that health, summary.json and report.html give.
double largestStd(const Mat3d& C);

/// The Jacobian of toVec6(delta^-1 T_prev^-1 T_cur) w.r.t. a right perturbation of T_prev at a
/// zero residual (T_rel = T_prev^-1 T_cur): [[-R^T, R^T [t]x], [0, -R^T]] with R, t of T_rel;
/// w.r.t. the current pose's it is the identity.
Mat6d relativeJacobianPrev(const SE3d& T_rel);

}  // namespace superloc::fusion
