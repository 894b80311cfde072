// Map and scan files: PCD (binary and ASCII, via PCL), PLY (ASCII and binary little-endian),
// KITTI .bin (float32 x y z reflectance) and MRPT text point maps (.txt/.xyz: "x y z [i]").
#pragma once

#include <superloc/core/types.h>

#include <string>

namespace superloc::io {

enum class CloudFormat { Auto, PcdBinary, PcdAscii, Ply, KittiBin, Text };

/// Loads a point cloud; the format is chosen by extension (.pcd .ply .bin .txt .xyz) unless
/// given. NaN/inf points are dropped and counted in `dropped` (if not null). Throws
/// std::runtime_error with a one-line message naming the file on a missing, truncated or
/// malformed file.
PointCloud loadPointCloud(
    const std::string& path, CloudFormat format = CloudFormat::Auto, size_t* dropped = nullptr);

/// Saves a point cloud (with intensity/normals/rgb when present). Auto picks by extension;
/// .pcd is written binary. Throws std::runtime_error naming the file on failure.
void savePointCloud(
    const std::string& path, const PointCloud& cloud, CloudFormat format = CloudFormat::Auto);

}  // namespace superloc::io
