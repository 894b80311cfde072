// The NDT registration (method = ndt, the hdl_localization family): PCL's NDT from the start
// pose on every deskewed voxel candidate (NdtAligner), then, with IMU, its pose as a measurement
// beside the IMU factor (loosely coupled) for velocity and biases. The alignment risk is
// reported from correspondences at the start pose (not used).
#pragma once

#include <superloc/localization/localizer_params.h>
#include <superloc/localization/ndt_aligner.h>
#include <superloc/localization/registration.h>

namespace superloc::localization {

class NdtRegistration final : public Registration {
   public:
    /// `assoc`: the tracking association (risk and quality correspondences).
    NdtRegistration(const LocalizerParams& params, const AssociationParams& assoc);
    /// The map's NDT grid (PreparedMap::ndt); set before solving.
    void setTarget(const NdtAligner* ndt) { ndt_ = ndt; }
    void solve(const RegistrationProblem& p, FrameSolution& sol) const override;
    /// Every candidate, one alignment, its correspondences at the start, no joint solve.
    Traits traits() const override {
        Traits t;
        t.all_candidates = true;
        t.coarse_to_fine = false;
        t.correspondences_at_solution = false;
        t.joint = false;
        return t;
    }

   private:
    fusion::FusionParams fusion_;
    imu::ImuParams imu_;
    risk::RiskParams risk_;
    AssociationParams assoc_;
    const NdtAligner* ndt_ = nullptr;
};

}  // namespace superloc::localization
