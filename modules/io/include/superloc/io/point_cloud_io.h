// Map and scan files: PCD (binary and ASCII, via PCL), PLY (ASCII and binary little-endian),
// KITTI .bin (float32 x y z reflectance), MRPT text point maps (.txt/.xyz: "x y z [i]"), MRPT
// .simplemap (every scan at its keyframe pose) and serialized MRPT point maps (.pointsmap),
// see mrpt_maps.h.
#pragma once

#include <superloc/core/types.h>

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace superloc::io {

/// Ply is written binary little-endian; PlyAscii writes ASCII PLY (both are read as Ply).
enum class CloudFormat {
    Auto, PcdBinary, PcdAscii, Ply, KittiBin, Text, PlyAscii,
    MrptSimpleMap,  ///< .simplemap: read only
    MrptPointsMap   ///< .pointsmap: a serialized CPointsMap (CPointsMapXYZI with intensity)
};

/// Loads a point cloud; the format is chosen by extension (.pcd .ply .bin .txt .xyz .simplemap
/// .pointsmap) unless
/// given. NaN/inf points are dropped and counted in `dropped` (if not null). Throws
/// std::runtime_error with a one-line message naming the file on a missing, truncated or
/// malformed file.
PointCloud loadPointCloud(const std::string& path, CloudFormat format = CloudFormat::Auto,
                          size_t* dropped = nullptr);

/// Saves a point cloud (with intensity/normals/rgb when present). Auto picks by extension;
/// .pcd is written binary. Throws std::runtime_error naming the file on failure.
void savePointCloud(const std::string& path, const PointCloud& cloud,
                    CloudFormat format = CloudFormat::Auto);

/// Writes points coloured by colour(i) as binary PLY (x y z, red green blue), reading them in
/// place: the bytes savePointCloud writes for that cloud (.ply), without building it (the
/// observability scan of a long run). Throws std::runtime_error naming the file on failure.
void saveColouredPly(const std::string& path, const std::vector<Vec3f>& points,
                     const std::function<std::array<uint8_t, 3>(size_t)>& colour);

/// The format chosen for a path by extension (case-insensitive); throws naming the file when
/// the extension is unknown.
CloudFormat formatFromExtension(const std::string& path);

/// Removes points with a NaN/inf coordinate (and their attributes); returns how many.
size_t dropNonFinite(PointCloud& cloud);

}  // namespace superloc::io
