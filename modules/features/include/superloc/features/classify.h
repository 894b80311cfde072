// Point / line / plane classification of a neighbourhood from its PCA shape factors
// (eigenvalues l1 >= l2 >= l3 of the covariance): planarity (l2 - l3) / l1, linearity
// (l1 - l2) / l1 (Demantké et al. 2011), as used for the paper's point, line and plane features.
#pragma once

#include <cstdint>

namespace superloc::features {

enum class FeatureType : uint8_t { Point = 0, Line = 1, Plane = 2 };

/// Plane when planarity >= plane_min; else line when linearity >= line_min; else point.
inline FeatureType classifyShape(float planarity, float linearity, double plane_min, double line_min) {
    if (planarity >= plane_min) return FeatureType::Plane;
    if (linearity >= line_min) return FeatureType::Line;
    return FeatureType::Point;
}

inline const char* featureTypeName(FeatureType t) {
    return t == FeatureType::Plane ? "plane" : t == FeatureType::Line ? "line" : "point";
}

}  // namespace superloc::features
