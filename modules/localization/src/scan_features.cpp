// Step 2: a scan's features (scan_features.h).
#include <superloc/localization/scan_features.h>

#include <algorithm>

namespace superloc::localization {

void ScanFeatures::redeskew(const Scan& scan, const features::SweepMotion& m) {
    motion = m;
    features::deskewPoints(scan.points, scan.rel_time, feature_idx, motion, deskewed);
    for (size_t i = 0; i < deskewed.size(); ++i) pts_body[i] = scan.T_imu_lidar * deskewed[i].cast<double>();
}

ScanFeatures strided(const ScanFeatures& ft, int most) {
    ScanFeatures out;
    const size_t n = ft.pts_body.size();
    if (most <= 0 || n <= static_cast<size_t>(most)) return out;
    const size_t k = (n + static_cast<size_t>(most) - 1) / static_cast<size_t>(most);
    const bool timed = ft.rel_time.size() == n;
    for (size_t i = 0; i < n; i += k) {
        out.pts_body.push_back(ft.pts_body[i]);
        if (timed) out.rel_time.push_back(ft.rel_time[i]);
    }
    out.T_imu_lidar = ft.T_imu_lidar;
    out.sweep_s = ft.sweep_s;
    return out;
}

bool Preprocessor::run(const Scan& scan, const Prediction& pred, const fusion::FrameState& prev,
                       const SensorHistory& sensors, const Vec3d& g_map, bool ndt, ScanFeatures& out) {
    out.T_imu_lidar = scan.T_imu_lidar;
    // NaN/range filter, one candidate per voxel, features spread evenly over the sweep.
    selector_.selectInRange(scan.points, static_cast<float>(p_.min_range), static_cast<float>(p_.max_range),
                            static_cast<float>(p_.voxel_size), out.valid, out.candidates);
    features::takeEvenly(out.candidates, static_cast<size_t>(p_.max_features), out.feature_idx);
    out.rel_time.clear();
    if (scan.rel_time.size() == scan.size())
        for (uint32_t i : out.feature_idx) out.rel_time.push_back(scan.rel_time[i]);

    // Deskew to the scan time with the predicted twist, seen from the LiDAR (doc/method.md §3).
    features::SweepMotion motion;
    bool deskewed = false;
    const float s_min = p_.deskew && scan.rel_time.size() == scan.size() && !scan.empty()
                            ? *std::min_element(scan.rel_time.begin(), scan.rel_time.end())
                            : 0.0f;
    out.sweep_s = s_min < 0 ? -double(s_min) : 0.0;
    if (pred.twist_from_imu || pred.from_odom || p_.deskew_without_imu) {
        if (s_min < 0) {
            if (p_.deskew_imu_poses && pred.used_imu) {
                // Along the IMU's trajectory from the previous state (its last pose is this
                // frame's prediction).
                const auto sp = imu::sweepPoses(sensors.imu(), prev.t, prev.nav(), prev.bias(), g_map, scan.t, s_min,
                                                scan.T_imu_lidar);
                motion = features::SweepMotion::fromSamples(sp.s, sp.T_end_s);
            } else {
                const Mat3d R_il = scan.T_imu_lidar.linear();
                const Vec3d w_l = R_il.transpose() * pred.w_body;
                const Vec3d v_l =
                    R_il.transpose() * (pred.v_body + pred.w_body.cross(scan.T_imu_lidar.translation()));
                motion = features::SweepMotion::fromTwist(v_l, w_l, -s_min);
            }
            deskewed = true;
        }
    }
    features::deskewPoints(scan.points, scan.rel_time, out.feature_idx, motion, out.deskewed);
    out.pts_body.resize(out.deskewed.size());
    for (size_t i = 0; i < out.deskewed.size(); ++i) out.pts_body[i] = scan.T_imu_lidar * out.deskewed[i].cast<double>();

    // NDT registers every voxel candidate, as hdl_localization feeds it a voxelized scan.
    if (ndt) features::deskewPoints(scan.points, scan.rel_time, out.candidates, motion, out.ndt_source);
    out.motion = motion;
    return deskewed;
}

}  // namespace superloc::localization
