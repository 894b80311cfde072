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

namespace superloc::fusion {

/// The scan information H without its noise floor: each eigen-direction of the translation
/// block keeps its eigenvalue minus `floor_share` of the block's trace (never below 0). A plane
/// normal with angular noise sigma_n puts a share of about sigma_n^2 of its information on every
/// direction across it by chance; that much holds nothing. The cross terms with the rotation
/// are scaled alike (H_eff = S H S, S = V diag(sqrt(kept / eigenvalue)) V^T on the translation,
/// identity on the rotation, whose degeneracies are exact zeros of the torques).
Mat6d informationAboveNoise(const Mat6d& H, double floor_share);

/// Where an estimate of information `info` is weak: per group, the eigen-directions u_i of its
/// covariance with std sigma_i above `weak_sigma` (translation, rotation) get the share
/// w_i = 1 - (weak / sigma_i)^2 (0 up to the weak std, 1 where nothing holds the direction).
struct Weakness {
    /// Per group U diag(sqrt(w)) U^T: a prior of information W on the body axes, applied along
    /// the weak directions only, is G W G.
    Mat6d G = Mat6d::Zero();
    /// Body axis k is weak when (G G)_kk >= 0.5: at least half of it lies in weak directions.
    std::array<bool, 6> weak{};
    /// Std per axis [m, rad] over the information's eigen-directions that make at least 5 % of
    /// the axis (the marginal, without a near-unheld direction's small component on it), capped
    /// at kMaxSigma where nothing holds the axis.
    Vec6d sigma = Vec6d::Zero();
    bool any() const;
};
inline constexpr double kMaxSigma = 1e3;
Weakness weakness(const Mat6d& info, const Vec6d& weak_sigma);

class EstimateInformation {
   public:
    /// Before a frame's scan: the information carried to the current state `in.cur` (its
    /// prediction) from the last committed frame through `in.imu`, starting from the fixed
    /// prior when nothing was committed. Without IMU nothing is carried. `in.prev_prior` is
    /// ignored (this filter keeps its own).
    void predict(const FrameProblemInputs& in, const FusionParams& params);
    /// The pose's information with the scan's `H` (informationAboveNoise) added.
    Mat6d information(const Mat6d& H) const;
    /// The frame is final at `cur`: carried + scan information becomes the next frame's prior.
    /// Without a carried information (no IMU) the filter starts again.
    void commit(const FrameState& cur, const Mat6d& H);
    /// Forget everything (after a relocalization, a divergence, a lost frame).
    void reset();

   private:
    std::optional<StatePrior> prior_;  ///< on the last committed state
    std::optional<Mat15d> carried_;    ///< on the current state, before its scan
};

}  // namespace superloc::fusion
