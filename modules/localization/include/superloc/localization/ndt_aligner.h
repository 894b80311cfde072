// PCL's NormalDistributionsTransform: aligns a scan to a target cloud (method=ndt, the
// hdl_localization family; NdtRegistration wraps it as a Registration). PCL stays inside ndt_aligner.cpp.
#pragma once

#include <superloc/core/types.h>

#include <memory>
#include <vector>

namespace superloc::localization {

struct NdtParams {
    double resolution = 1.0;   ///< [m] cell size
    double step_size = 0.1;    ///< [m]
    double epsilon = 1e-4;
    int max_iterations = 30;
};

struct AlignResult {
    SE3d T_target_source = SE3d::Identity();
    bool converged = false;
    int iterations = 0;
};

class NdtAligner {
   public:
    NdtAligner(const std::vector<Vec3f>& target, const NdtParams& params);
    ~NdtAligner();
    NdtAligner(const NdtAligner&) = delete;
    NdtAligner& operator=(const NdtAligner&) = delete;

    /// Aligns source (its own frame) to the target starting from the guess T_target_source.
    AlignResult align(const std::vector<Vec3f>& source, const SE3d& guess) const;

   private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace superloc::localization
