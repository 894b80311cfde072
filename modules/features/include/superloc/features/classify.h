// Point / line / plane classification of a neighbourhood from its PCA shape factors
// (eigenvalues l1 >= l2 >= l3 of the covariance): planarity (l2 - l3) / l1, linearity
// (l1 - l2) / l1 (Demantké et al. 2011), as used for the paper's point, line and plane features.
#pragma once

#include <superloc/core/correspondence.h>

#include <cstdint>

namespace superloc::features {

/// Thickness l3 / l2 of a neighbourhood from its shape factors (1 when l2 vanishes).
inline float shapeThickness(float planarity, float linearity) {
    const float r2 = 1.0f - linearity;              // l2 / l1
    const float r3 = 1.0f - linearity - planarity;  // l3 / l1
    return r2 > 1e-6f ? r3 / r2 : 1.0f;
}

/// Plane when the neighbourhood is thin (l3 / l2 <= plane_max_thickness) and not a mere strip
/// (l2 / l1 >= 0.05); else line when linearity >= line_min; else point. (Planarity alone
/// would call the elongated plane patches of ring-structured LiDAR maps "not planar".)
inline FeatureType classifyShape(float planarity, float linearity, double plane_max_thickness,
                                 double line_min) {
    if (shapeThickness(planarity, linearity) <= plane_max_thickness && 1.0f - linearity >= 0.05f)
        return FeatureType::Plane;
    if (linearity >= line_min) return FeatureType::Line;
    return FeatureType::Point;
}

}  // namespace superloc::features
