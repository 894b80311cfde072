// Private to io: one reader/writer pair per map file format (dispatched by point_cloud_io.cpp).
// Readers keep NaN/inf points (the caller drops and counts them) and throw std::runtime_error
// with a one-line message naming the file.
#pragma once

#include <superloc/core/types.h>

#include <string>

namespace superloc::io::detail {

PointCloud readPcd(const std::string& path);
void writePcd(const std::string& path, const PointCloud& cloud, bool binary);

PointCloud readPly(const std::string& path);
void writePly(const std::string& path, const PointCloud& cloud, bool binary);

PointCloud readKittiBin(const std::string& path);
void writeKittiBin(const std::string& path, const PointCloud& cloud);

PointCloud readText(const std::string& path);
void writeText(const std::string& path, const PointCloud& cloud);

}  // namespace superloc::io::detail
