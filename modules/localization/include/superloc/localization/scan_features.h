// Step 2 of a frame (doc/localizer.md): the scan's features for registration. NaN/range filter
// and one candidate per voxel in one pass, at most max_features taken evenly over the sweep,
// deskewed to the scan time along the predicted motion, moved to the body (IMU) frame.
#pragma once

#include <superloc/features/deskew.h>
#include <superloc/features/features_params.h>
#include <superloc/features/voxel_selector.h>
#include <superloc/fusion/state.h>
#include <superloc/localization/frame_report.h>
#include <superloc/localization/motion_model.h>
#include <superloc/localization/sensor_history.h>

#include <vector>

namespace superloc::localization {

/// One scan's features (indices into Scan::points) and the sweep motion they are deskewed by.
struct ScanFeatures {
    std::vector<uint32_t> valid;        ///< points in range
    std::vector<uint32_t> candidates;   ///< one valid point per features.voxel_size voxel
    std::vector<uint32_t> feature_idx;  ///< the candidates used (capped, spread over the sweep)
    std::vector<Vec3f> deskewed;        ///< the features deskewed, LiDAR frame at the scan time
    std::vector<Vec3d> pts_body;        ///< ... in the body frame: what registration aligns
    std::vector<float> rel_time;        ///< [s] ... their points' times relative to the scan's; empty when untimed
    std::vector<Vec3f> ndt_source;      ///< method ndt: every candidate, deskewed
    features::SweepMotion motion;       ///< the motion over the sweep the points are deskewed by
    /// [s] the sweep's span (−min of the points' relative times) where `[features] deskew` is on
    /// and the points are timed; 0 otherwise
    double sweep_s = 0;
    SE3d T_imu_lidar = SE3d::Identity();

    /// Deskews the features again along `m` (the sweep velocity estimated with the pose).
    void redeskew(const Scan& scan, const features::SweepMotion& m);
};

/// Every k-th of `ft`'s features (body points and times), k the smallest that leaves at most
/// `most`; empty when all are kept (`most` 0, or no more than that many). For solves that only
/// have to land in a basin: the last-scan registration, a search's hypotheses.
ScanFeatures strided(const ScanFeatures& ft, int most);

/// Fills ScanFeatures from a scan and its prediction; keeps its selection table between scans
/// (no allocation per frame once warm).
class Preprocessor {
   public:
    explicit Preprocessor(const features::FeaturesParams& p) : p_(p) {}
    /// `prev`: the previous frame's state, from which the IMU's sweep poses are integrated
    /// (features.deskew_imu_poses); `ndt`: also deskew every candidate (method ndt). Returns
    /// whether the sweep was deskewed.
    bool run(const Scan& scan, const Prediction& pred, const fusion::FrameState& prev, const SensorHistory& sensors,
             const Vec3d& g_map, bool ndt, ScanFeatures& out);

   private:
    features::FeaturesParams p_;
    features::VoxelSelector selector_;
};

}  // namespace superloc::localization
