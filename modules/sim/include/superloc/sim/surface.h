// Dense surface sampling of a world mesh: the survey ("FARO") map and the prior map.
#pragma once

#include <superloc/core/types.h>
#include <superloc/sim/mesh.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace superloc::sim {

/// Cells within `radius` of any of the given points (a coarse 3-D mask, cell = radius / 8).
class NearMask {
 public:
    NearMask(const std::vector<Vec3d>& centres, double radius);
    bool contains(const Vec3f& p) const;

 private:
    double cell_;
    std::vector<uint64_t> keys_;  // sorted
};

/// Uniform random samples on the mesh surfaces, one per `spacing`^2 of area on average (with
/// the triangle's unit normal). Only samples accepted by `keep` (if given) are returned.
PointCloud sampleSurface(const Mesh& mesh, double spacing, uint64_t seed,
                         const std::function<bool(const Vec3f&)>& keep = {});

/// The map a user would be handed: surface samples voxel-downsampled, then displaced by white
/// noise (`noise` sigma) and a smooth warp (`warp` amplitude over ~10 m). Normals are dropped.
PointCloud makePriorMap(const PointCloud& samples, double voxel, double noise, double warp,
                        uint64_t seed);

}  // namespace superloc::sim
