// The ICP registration (doc/localizer.md steps 3-5): associate at the current estimate, measure
// the alignment risk, solve scan + IMU + prior jointly (fusion::solveFrame), repeat, coarse to
// fine. The association is the run's (association.h: nearest map point, voxel map, or the
// hybrid); a hypothesis is solved in the voxel map whatever it is.
#pragma once

#include <superloc/localization/localizer_params.h>
#include <superloc/localization/registration.h>

#include <optional>
#include <vector>

namespace superloc::localization {

class IcpRegistration final : public Registration {
   public:
    explicit IcpRegistration(const LocalizerParams& params);
    void solve(const RegistrationProblem& p, FrameSolution& sol) const override;
    /// The tracking association at the finest level (the frame's quality is measured with it).
    const AssociationParams& association() const { return assoc_; }

   private:
    /// The coarse-to-fine schedule of one solve: each round's resolution (voxel level or search
    /// radius) and robust-kernel scale, and when the solve has converged (icp_registration.cpp).
    class Schedule;
    /// What one round did: stopped before its solve (too few correspondences), its solve failed,
    /// or it moved the pose by `step_xyz` [m] / `step_rad`.
    struct Round {
        enum class End { Solved, Sparse, Unusable } end = End::Solved;
        double step_xyz = 0, step_rad = 0;
    };
    /// One solve's working state, kept across its rounds: each correspondence's feature, each
    /// feature's nearest map point of the last round (associate's nearest_hint), and whether the
    /// risk step found the frame weak in translation (planes: no voxel planes from then on).
    static AssociationMemo& freshMemo();
    struct Scratch {
        std::vector<uint32_t> feature_of, nearest_hint;
        bool point_geometry = false;
        /// planes: the fallback's answers, for the rounds after the first (the thread's, cleared
        /// for each solve: its memory is kept from one frame to the next)
        AssociationMemo& memo = freshMemo();
    };
    /// Round `r` of `rounds` at `s`'s resolution (steps 3-5): associate at sol's state, the risk
    /// and the fusion's prior where `s` says, the joint solve from the window's previous state
    /// `prev_saved`, the fusion's amendment; sol and its report get what it solved.
    Round round(const RegistrationProblem& p, const Schedule& s, int r, int rounds, const fusion::FrameState& prev_saved,
                std::optional<fusion::RelativePosePrior>& prior, Scratch& scratch, FrameSolution& sol) const;
    /// sol's correspondences at T with `ap` (each with its point's time in the sweep).
    void associateAt(const RegistrationProblem& p, const SE3d& T, const AssociationParams& ap, Scratch& scratch,
                     FrameSolution& sol) const;

    LocalizationParams lp_;
    fusion::FusionParams fusion_;
    imu::ImuParams imu_;
    risk::RiskParams risk_;
    AssociationParams assoc_;
    fusion::RobustKernel kernel_;
};

/// A solve needs this many correspondences for its scan factor.
inline constexpr size_t kMinCorrespondences = 10;

}  // namespace superloc::localization
