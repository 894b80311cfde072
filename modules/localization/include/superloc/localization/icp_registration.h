// The ICP registration (doc/localizer.md steps 3-5): associate at the current estimate, measure
// the alignment risk, solve scan + IMU + prior jointly (fusion::solveFrame), repeat, coarse to
// fine. The association is the run's (association.h: nearest map point, voxel map, or the
// hybrid); a hypothesis is solved in the voxel map whatever it is.
#pragma once

#include <superloc/localization/localizer_params.h>
#include <superloc/localization/registration.h>

namespace superloc::localization {

class IcpRegistration final : public Registration {
   public:
    explicit IcpRegistration(const LocalizerParams& params);
    void solve(const RegistrationProblem& p, FrameSolution& sol, FrameReport& rep) const override;
    /// The tracking association at the finest level (the frame's quality is measured with it).
    const AssociationParams& association() const { return assoc_; }

   private:
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
