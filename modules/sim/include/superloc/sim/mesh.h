// Triangle meshes for the synthetic worlds, and the primitives the world builders use.
#pragma once

#include <superloc/core/types.h>

#include <cstdint>
#include <vector>

namespace superloc::sim {

/// An indexed triangle mesh in the map frame, with a LiDAR reflectivity per triangle.
struct Mesh {
    std::vector<Vec3f> vertices;             ///< [m] map frame
    std::vector<Eigen::Vector3i> triangles;  ///< vertex indices
    std::vector<float> reflectivity;         ///< [0..1] one per triangle

    size_t size() const { return triangles.size(); }

    void addTriangle(const Vec3d& a, const Vec3d& b, const Vec3d& c, float refl = 0.5f);
    /// Planar quad a-b-c-d (in order around its border), as two triangles.
    void addQuad(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d, float refl = 0.5f);
    /// Quad subdivided in n_u x n_v cells (long walls: keeps triangles small for the BVH).
    void addGridQuad(const Vec3d& origin, const Vec3d& u, const Vec3d& v, int n_u, int n_v,
                     float refl = 0.5f);
    /// Axis-aligned box [lo, hi] (all six faces).
    void addBox(const Vec3d& lo, const Vec3d& hi, float refl = 0.5f);
    /// Box of size (sx, sy, sz) centred at `center` (z = bottom face), rotated by yaw about z.
    void addOrientedBox(const Vec3d& bottom_center, const Vec3d& size, double yaw,
                        float refl = 0.5f);
    /// Vertical cylinder (side + top) on `bottom_center`, `segments` facets.
    void addCylinder(const Vec3d& bottom_center, double radius, double height, int segments = 16,
                     float refl = 0.5f);
    /// Appends another mesh.
    void append(const Mesh& other);

    /// Unit normal of triangle i (right-handed from its vertex order).
    Vec3d normal(size_t i) const;
    /// Area [m^2] of triangle i.
    double area(size_t i) const;
    /// Axis-aligned bounds of all vertices.
    void bounds(Vec3d& lo, Vec3d& hi) const;
};

}  // namespace superloc::sim
