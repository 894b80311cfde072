// What the estimate knows of each direction without odom_alt (active fusion, doc/method.md §2):
// the scan's information above its noise floor plus what the IMU window carries from the frames
// before. The paper's risk asks "is the *scan* blind along x?"; this asks "is the *estimate*
// weak along x?", which is what decides whether a second odometry can help there.
//
// EstimateInformation is an information filter that runs beside the solver: each frame, the last
// frame's information is carried through the IMU factor (the prediction), the scan's information
// is added on the pose, and the sum is the next frame's prior. It is the solver's own marginal
// with one difference: the scan enters without its noise floor (informationAboveNoise). The
// small components of noisy wall normals along a corridor's axis give a full Hessian about
// 1/(2.5 cm)^2 per frame along that axis where nothing holds it; counted frame after frame they
// would make the estimate look sure of it.
//
// All 6-vectors and 6 x 6 matrices: (x y z roll pitch yaw), body axes, a right perturbation
// T Exp(d) (the coordinates of scanInformation).
#pragma once

#include <superloc/core/types.h>
#include <superloc/fusion/frame_problem.h>

#include <array>
#include <optional>
#include <vector>

namespace superloc::fusion {

/// The scan information H without its noise floor: each eigen-direction of the translation
/// block keeps its eigenvalue minus `floor_share` of the block's trace (never below 0). A plane
/// normal with angular noise sigma_n puts a share of about sigma_n^2 of its information on every
/// direction across it by chance; that much holds nothing. The cross terms with the rotation
/// are scaled alike (H_eff = S H S, S = V diag(sqrt(kept / eigenvalue)) V^T on the translation,
/// identity on the rotation, whose degeneracies are exact zeros of the torques).
Mat6d informationAboveNoise(const Mat6d& H, double floor_share);
/// Another information `G` of the same residuals (e.g. reweighted) scaled as H's floor scales H:
/// S G S with H's S.
Mat6d informationAboveNoise(const Mat6d& H, double floor_share, const Mat6d& G);

/// Where an estimate of information `info` is weak: per group, the eigen-directions u_i of its
/// covariance, with std sigma_i, get the share w_i = sigma_i^2 / (sigma_i^2 + weak^2) (`weak_sigma`:
/// translation, rotation): the paper's 1 - gamma with gamma the estimate's confidence along
/// u_i, sigma_weak^2 / (sigma_weak^2 + sigma_i^2): ~0 where the estimate is sure, 1/2 at the
/// weak std, -> 1 where nothing holds u_i.
struct Weakness {
    /// Per group U diag(sqrt(w)) U^T: a prior of information W on the body axes, applied along
    /// the weak directions only, is G W G.
    Mat6d G = Mat6d::Zero();
    /// Body axis k is weak when (G G)_kk >= 0.5: its share of weak directions is at least half.
    std::array<bool, 6> weak{};
    /// Std per axis [m, rad] over the information's eigen-directions that make at least 5 % of
    /// the axis (the marginal, without a near-unheld direction's small component on it), capped
    /// at kMaxSigma where nothing holds the axis.
    Vec6d sigma = Vec6d::Zero();
    bool any() const;
};
inline constexpr double kMaxSigma = 1e3;
/// The covariance of an information matrix with its unheld directions at kMaxSigma (a
/// pseudo-inverse that stays finite; weakness() and PosePosterior use it).
Mat6d cappedCovariance(const Mat6d& info);
/// What the information `H` says of the rest when the pose is left free along the direction `u`
/// (unit, body perturbation coordinates): its Schur complement in a basis with u first,
/// H - H u (u^T H u)^-1 u^T H, so that u^T H' = 0. The information of a measurement whose say
/// along u is not taken. Not P H P with P projecting u out, which is not below H and can add
/// information along a direction H left free (a corridor's axis coupled with pitch and yaw).
Mat6d withoutDirection(const Mat6d& H, const Vec6d& u);
/// The direction (body perturbation coordinates, translation only) along which a frame should
/// not take its scan (doc/method.md §4, "Beyond the association's reach"): the position's most
/// uncertain direction under the carried information `carried`, when its std there exceeds
/// `reach` [m] and the risk says the scan does not hold the body axis nearest it (`gamma` below
/// `weak_gamma`). None when nothing is carried (a first frame, a reset filter: the scan is all
/// there is) or the scan may be taken.
std::optional<Vec6d> beyondReach(const Mat6d& carried, const Vec6d& gamma, double weak_gamma, double reach);
Weakness weakness(const Mat6d& info, const Vec6d& weak_sigma);

class EstimateInformation {
   public:
    /// `floor_share`: informationAboveNoise's; `weak_xyz` [m]: the weak translation std.
    explicit EstimateInformation(double floor_share = 0.0049, double weak_xyz = 0.05)
        : floor_share_(floor_share), weak_xyz_(weak_xyz) {}
    /// Before a frame's scan: the information carried to the current state `in.cur` (its
    /// prediction) from the last committed frame through `in.imu`, starting from the fixed
    /// prior when nothing was committed. Without IMU nothing is carried. `in.prev_prior` is
    /// ignored (this filter keeps its own).
    void predict(const FrameProblemInputs& in, const FusionParams& params);
    /// The pose's information with the scan's `H` (informationAboveNoise) added. Along a
    /// translation direction the carried information leaves weak, the scan counts only where
    /// its share is above the noise floor: each frame's wall normals are estimated a few
    /// tenths of a degree off, and without this their spread, frame after frame, would teach
    /// the filter the corridor's axis (measured: x held at 0.2 m after a minute of nothing).
    Mat6d information(const Mat6d& H) const;
    /// The frame is final at `cur`: carried + scan information becomes the next frame's prior.
    /// Without a carried information (no IMU) the filter starts again.
    void commit(const FrameState& cur, const Mat6d& H);
    /// Forget everything (after a relocalization, a divergence, a lost frame).
    void reset();
    /// The variance of the IMU-carried prediction's body motion over a frame of `dt` seconds,
    /// per body axis (x y z roll pitch yaw), for the body rotation `R_map_imu`: the carried
    /// velocity's and gyro bias's covariance times dt^2 (what the prediction does not know of
    /// the motion since the last frame). Empty before predict() or without IMU.
    std::optional<Vec6d> motionVariance(double dt, const Mat3d& R_map_imu) const;

    /// The scan information `H` without its part along the carried covariance's weak
    /// translation directions where that part is below the noise floor (what information()
    /// adds; the pose's covariance adds the same, PosePosterior). `H` itself before predict().
    Mat6d scanPart(const Mat6d& H) const;

   private:
    double floor_share_, weak_xyz_;
    std::optional<StatePrior> prior_;  ///< on the last committed state
    std::optional<Mat15d> carried_;    ///< on the current state, before its scan
    /// Translation directions (unit, body) along which carried_ leaves the pose's std above
    /// weak_xyz_: set by predict().
    std::vector<Eigen::Vector3d> weak_dirs_;
};

}  // namespace superloc::fusion
