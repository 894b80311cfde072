// The observability scan (paper Fig. 4): the localized correspondence points of the whole run,
// coloured by their translation observability label (x red, y green, z blue, none grey; see
// risk::observabilityColor), one point per voxel so that it stays bounded on long runs. A voxel
// keeps its first point and is coloured by the label seen most often in it.
#pragma once

#include <superloc/core/types.h>
#include <superloc/core/voxel.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace superloc::app {

class ObservabilityScan {
 public:
    /// voxel [m] > 0 (std::invalid_argument otherwise).
    explicit ObservabilityScan(double voxel);

    /// Points in the map frame with their translation labels (0 x, 1 y, 2 z, other: none).
    void add(const std::vector<Vec3f>& points, const std::vector<int8_t>& labels);
    /// The coloured cloud (points + rgb), in order of first occurrence.
    PointCloud cloud() const;
    size_t size() const { return voxels_.size(); }
    /// Writes the cloud as binary PLY through a temporary file renamed into place, so a reader
    /// (or a crash while writing) never sees a half-written file; the points are read in place
    /// (no copy of the cloud). Throws naming the path.
    void write(const std::string& path) const;
    /// Resident bytes of the voxels and their votes.
    size_t memoryBytes() const;

 private:
    /// The colour of voxel i: its most frequent label's.
    std::array<uint8_t, 3> colour(size_t i) const;
    VoxelFirstPoints voxels_;  ///< each voxel's first point (20-28 bytes a voxel with its slots)
    std::vector<std::array<uint32_t, 4>> votes_;  ///< x, y, z, none
};

}  // namespace superloc::app
