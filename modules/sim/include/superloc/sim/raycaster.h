// Ray casting against a triangle mesh with Embree 3 (one device, single-threaded, deterministic).
#pragma once

#include <superloc/sim/mesh.h>

#include <memory>

namespace superloc::sim {

/// The first surface a ray meets.
struct RayHit {
    bool hit = false;
    double range = 0;               ///< [m] distance along the (unit) direction
    uint32_t triangle = 0;          ///< index into Mesh::triangles
    Vec3d normal = Vec3d::UnitZ();  ///< unit geometric normal (not flipped)
};

/// Owns the Embree device and scene built from a mesh (the mesh is copied into Embree buffers).
class RayCaster {
 public:
    explicit RayCaster(const Mesh& mesh);
    ~RayCaster();
    RayCaster(const RayCaster&) = delete;
    RayCaster& operator=(const RayCaster&) = delete;

    /// Casts one ray; `dir` must be a unit vector. Only hits in [t_min, t_max] count.
    RayHit cast(const Vec3d& origin, const Vec3d& dir, double t_min, double t_max) const;

    /// Casts a batch of rays sharing one origin (a LiDAR column): dirs are unit vectors.
    /// Uses Embree's 16-wide packets; results in `out` (resized to dirs.size()).
    void castFan(const Vec3d& origin, const std::vector<Vec3d>& dirs, double t_min, double t_max,
                 std::vector<RayHit>& out) const;

 private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace superloc::sim
