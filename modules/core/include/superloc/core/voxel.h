// Voxel-grid downsampling on a hash grid (MRPT 2.5.8 has none for point maps).
#pragma once

#include <superloc/core/types.h>

#include <cstdint>
#include <vector>

namespace superloc {

/// Integer voxel key of a point for a given voxel size (64-bit: a small voxel far from the
/// origin, e.g. 1e-9 m at 10 m, needs more than 32 bits).
struct VoxelKey {
    int64_t x, y, z;
    bool operator==(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct VoxelKeyHash {
    size_t operator()(const VoxelKey& k) const {
        return (static_cast<size_t>(k.x) * 73856093u) ^ (static_cast<size_t>(k.y) * 19349669u) ^
               (static_cast<size_t>(k.z) * 83492791u);
    }
};
/// floor(p / voxel) per axis. Throws std::invalid_argument naming the voxel size and the point
/// when an index does not fit in 62 bits (a voxel far below the float resolution of the point,
/// or a non-finite point), rather than merging distant points into one voxel.
VoxelKey voxelKey(const Vec3f& p, float voxel);

/// For each occupied voxel, the index of the point kept: the one closest to the voxel's
/// centroid (so kept points are real measurements, attributes stay consistent). Indices are
/// returned in order of first occurrence, so the output is deterministic. voxel <= 0 keeps all.
std::vector<uint32_t> voxelDownsampleIndices(const std::vector<Vec3f>& points, float voxel);

/// The same, applied to every attribute of a cloud.
PointCloud voxelDownsample(const PointCloud& cloud, float voxel);

/// Selects the given indices of every attribute of a cloud.
PointCloud selectIndices(const PointCloud& cloud, const std::vector<uint32_t>& idx);

}  // namespace superloc
