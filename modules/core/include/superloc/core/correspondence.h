// One scan-to-map correspondence: the project's one type for it. The localizer's association
// fills it, fusion's scan factor turns it into residuals (point-to-plane, -line, -point) and the
// risk step labels it (doc/design.md#4-per-frame-pipeline).
#pragma once

#include <superloc/core/types.h>

#include <cstdint>

namespace superloc {

/// Shape of the map neighbourhood a scan point is matched to (features::classifyShape).
enum class FeatureType : uint8_t { Point = 0, Line = 1, Plane = 2 };

inline const char* featureTypeName(FeatureType t) {
    return t == FeatureType::Plane ? "plane" : t == FeatureType::Line ? "line" : "point";
}

struct Correspondence {
    Vec3d p = Vec3d::Zero();   ///< [m] scan point in the body (IMU) frame
    Vec3d q = Vec3d::Zero();   ///< [m] map anchor point (map frame): on the plane / line, or the point
    Vec3d n = Vec3d::UnitZ();  ///< plane: unit normal; line: unit direction; point: unused
    FeatureType type = FeatureType::Plane;
    /// [s] the scan point's time relative to the scan's (<= 0 within the sweep; 0 when untimed):
    /// what the sweep's undone motion displaced it by depends on it (Tracker::sweepCovariance)
    float rel_time = 0.0f;
    double weight = 1.0;       ///< fit quality in [0, 1]; <= 0: ignored by the risk step
};

}  // namespace superloc
