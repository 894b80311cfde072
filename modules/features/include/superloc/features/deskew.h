// Deskew (motion compensation) of a sweep: each point, measured at its own time t + rel_time,
// is moved into the sensor frame at the scan time t (doc/design.md#3-data-conventions: the end of the sweep).
#pragma once

#include <superloc/core/types.h>

#include <cstdint>
#include <vector>

namespace superloc::features {

/// The sensor's motion over one sweep: T_end_s = pose at relative time s (s <= 0) expressed in
/// the sensor frame at s = 0, sampled on a table and interpolated (translation linearly, rotation
/// by its rotation vector), so that per-point evaluation is cheap.
class SweepMotion {
   public:
    SweepMotion() = default;
    /// Constant body twist over the sweep (v [m/s], w [rad/s] in the sensor frame at the end):
    /// T_end_s = (Exp(w s), v s) — the constant-velocity model.
    static SweepMotion fromTwist(const Vec3d& v, const Vec3d& w, double duration, int samples = 16);
    /// From poses T_end_s at increasing relative times s (last one should be 0), e.g. from IMU.
    static SweepMotion fromSamples(const std::vector<double>& s, const std::vector<SE3d>& T_end_s);

    bool empty() const { return s_.empty(); }
    /// Pose at s (clamped to the table range) as rotation vector + translation.
    void at(float s, Eigen::Vector3f& rotvec, Eigen::Vector3f& trans) const;
    /// Transforms a point measured at relative time s into the end frame.
    Vec3f apply(const Vec3f& p, float s) const;

   private:
    std::vector<float> s_;
    std::vector<Eigen::Vector3f> rot_, trans_;
};

/// Deskews the points `idx` of `points` (with per-point `rel_time`) into `out` (resized to
/// idx.size()). When rel_time is empty or the motion is empty, copies the points unchanged.
void deskewPoints(const std::vector<Vec3f>& points, const std::vector<float>& rel_time,
                  const std::vector<uint32_t>& idx, const SweepMotion& motion,
                  std::vector<Vec3f>& out);

}  // namespace superloc::features
