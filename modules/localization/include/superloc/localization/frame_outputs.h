// What a run's outputs need of a frame (superloc-localize's localized map and observability
// scan, doc/localizer.md "Outputs"): asked of Localizer::process with the frame, computed from
// the frame's result after its time is taken.
#pragma once

#include <superloc/features/voxel_selector.h>
#include <superloc/localization/registration.h>
#include <superloc/localization/scan_features.h>
#include <superloc/risk/alignment_risk.h>

#include <vector>

namespace superloc::localization {

struct FrameOutputs {
    /// [m] > 0: the scan's valid points, deskewed like its features, one per `map_voxel` voxel,
    /// in the map frame at the frame's solved pose (the localized map).
    double map_voxel = 0;
    std::vector<Vec3f> map_points;
    /// The observability scan (paper Fig. 4): the frame's final correspondence points in the map
    /// frame at its solved pose, with their translation label (0 x, 1 y, 2 z, risk::kNoLabel)
    /// from the risk rule at that pose.
    bool observability = false;
    std::vector<Vec3f> obs_points;
    std::vector<int8_t> obs_labels;
};

/// Fills FrameOutputs (keeps its voxel table between frames).
class OutputMaker {
   public:
    explicit OutputMaker(const risk::RiskParams& risk) : risk_(risk) { risk_.hessian_eigen = false; }
    void fill(const Scan& scan, const ScanFeatures& features, const FrameSolution& sol, FrameOutputs& out);

   private:
    risk::RiskParams risk_;
    features::VoxelSelector selector_;
    std::vector<uint32_t> idx_;
};

}  // namespace superloc::localization
