// Map/scan file dispatch by format, NaN dropping; KITTI .bin and text formats.
#include <superloc/io/mrpt_maps.h>
#include <superloc/io/point_cloud_io.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "cloud_formats.h"

namespace superloc::io {

CloudFormat formatFromExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext == ".pcd") return CloudFormat::PcdBinary;
    if (ext == ".ply") return CloudFormat::Ply;
    if (ext == ".bin") return CloudFormat::KittiBin;
    if (ext == ".txt" || ext == ".xyz") return CloudFormat::Text;
    if (ext == ".simplemap") return CloudFormat::MrptSimpleMap;
    if (ext == ".pointsmap") return CloudFormat::MrptPointsMap;
    throw std::runtime_error(path + ": unknown point-cloud extension '" + ext +
                             "' (use .pcd .ply .bin .txt .xyz .simplemap .pointsmap)");
}

size_t dropNonFinite(PointCloud& c) {
    const size_t n = c.points.size();
    const bool has_i = c.intensity.size() == n, has_n = c.normals.size() == n,
               has_c = c.rgb.size() == n;
    size_t w = 0;
    for (size_t r = 0; r < n; ++r) {
        if (!c.points[r].allFinite()) continue;
        c.points[w] = c.points[r];
        if (has_i) c.intensity[w] = c.intensity[r];
        if (has_n) c.normals[w] = c.normals[r];
        if (has_c) c.rgb[w] = c.rgb[r];
        ++w;
    }
    c.points.resize(w);
    if (has_i) c.intensity.resize(w);
    if (has_n) c.normals.resize(w);
    if (has_c) c.rgb.resize(w);
    return n - w;
}

PointCloud loadPointCloud(const std::string& path, CloudFormat format, size_t* dropped) {
    if (!std::filesystem::exists(path)) throw std::runtime_error(path + ": file not found");
    if (format == CloudFormat::Auto) format = formatFromExtension(path);
    PointCloud c;
    switch (format) {
        case CloudFormat::PcdBinary:
        case CloudFormat::PcdAscii:
            c = detail::readPcd(path);
            break;
        case CloudFormat::Ply:
        case CloudFormat::PlyAscii:
            c = detail::readPly(path);
            break;
        case CloudFormat::KittiBin:
            c = detail::readKittiBin(path);
            break;
        case CloudFormat::Text:
            c = detail::readText(path);
            break;
        case CloudFormat::MrptSimpleMap:
            c = loadSimpleMap(path);
            break;
        case CloudFormat::MrptPointsMap:
            c = loadMrptPointsMap(path);
            break;
        case CloudFormat::Auto:
            break;
    }
    const size_t n = dropNonFinite(c);
    if (dropped) *dropped = n;
    return c;
}

void savePointCloud(const std::string& path, const PointCloud& cloud, CloudFormat format) {
    const size_t n = cloud.size();
    if ((!cloud.intensity.empty() && cloud.intensity.size() != n) ||
        (!cloud.normals.empty() && cloud.normals.size() != n) ||
        (!cloud.rgb.empty() && cloud.rgb.size() != n))
        throw std::runtime_error(path + ": cannot save: attribute sizes differ from point count");
    if (format == CloudFormat::Auto) format = formatFromExtension(path);
    switch (format) {
        case CloudFormat::PcdBinary:
            detail::writePcd(path, cloud, true);
            break;
        case CloudFormat::PcdAscii:
            detail::writePcd(path, cloud, false);
            break;
        case CloudFormat::Ply:
            detail::writePly(path, cloud, true);
            break;
        case CloudFormat::PlyAscii:
            detail::writePly(path, cloud, false);
            break;
        case CloudFormat::KittiBin:
            detail::writeKittiBin(path, cloud);
            break;
        case CloudFormat::Text:
            detail::writeText(path, cloud);
            break;
        case CloudFormat::MrptPointsMap:
            saveMrptPointsMap(path, cloud);
            break;
        case CloudFormat::MrptSimpleMap:
            throw std::runtime_error(path + ": cannot write a map as a .simplemap (keyframes and "
                                     "observations); use .pointsmap for an MRPT point map");
        case CloudFormat::Auto:
            break;
    }
}

namespace detail {

PointCloud readKittiBin(const std::string& path) {
    const auto bytes = std::filesystem::file_size(path);
    if (bytes % (4 * sizeof(float)) != 0)
        throw std::runtime_error(path + ": truncated KITTI .bin (" + std::to_string(bytes) +
                                 " bytes is not a multiple of 16: float32 x y z reflectance)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    const size_t n = bytes / (4 * sizeof(float));
    std::vector<float> buf(4 * n);
    in.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(bytes));
    if (!in) throw std::runtime_error(path + ": read error");
    PointCloud c;
    c.points.resize(n);
    c.intensity.resize(n);
    for (size_t i = 0; i < n; ++i) {
        c.points[i] = Vec3f(buf[4 * i], buf[4 * i + 1], buf[4 * i + 2]);
        c.intensity[i] = buf[4 * i + 3];
    }
    return c;
}

void writeKittiBin(const std::string& path, const PointCloud& c) {
    std::vector<float> buf(4 * c.size());
    for (size_t i = 0; i < c.size(); ++i) {
        buf[4 * i] = c.points[i].x();
        buf[4 * i + 1] = c.points[i].y();
        buf[4 * i + 2] = c.points[i].z();
        buf[4 * i + 3] = c.intensity.empty() ? 0.0f : c.intensity[i];
    }
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error(path + ": cannot write");
    out.write(reinterpret_cast<const char*>(buf.data()),
              static_cast<std::streamsize>(buf.size() * sizeof(float)));
    if (!out) throw std::runtime_error(path + ": write error");
}

PointCloud readText(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open");
    PointCloud c;
    std::string line;
    size_t lineno = 0;
    int cols = -1;  // 3 or 4, fixed by the first data line
    while (std::getline(in, line)) {
        ++lineno;
        const size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#' || line[first] == '%') continue;
        std::istringstream ss(line);
        float v[4];
        int k = 0;
        std::string tok;
        while (ss >> tok) {
            if (k == 4)
                throw std::runtime_error(path + ":" + std::to_string(lineno) +
                                         ": more than 4 columns (expected 'x y z [i]')");
            char* end = nullptr;
            v[k] = std::strtof(tok.c_str(), &end);
            if (end != tok.c_str() + tok.size())
                throw std::runtime_error(path + ":" + std::to_string(lineno) + ": not a number: '" +
                                         tok + "'");
            ++k;
        }
        if (k < 3 || (cols != -1 && k != cols))
            throw std::runtime_error(
                path + ":" + std::to_string(lineno) + ": expected 'x y z [i]' (" +
                std::to_string(cols == -1 ? 3 : cols) + " columns), got " + std::to_string(k));
        cols = k;
        c.points.emplace_back(v[0], v[1], v[2]);
        if (k == 4) c.intensity.push_back(v[3]);
    }
    if (in.bad()) throw std::runtime_error(path + ": read error");
    return c;
}

void writeText(const std::string& path, const PointCloud& c) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw std::runtime_error(path + ": cannot write");
    const bool has_i = !c.intensity.empty();
    for (size_t i = 0; i < c.size(); ++i) {
        const auto& p = c.points[i];
        if (has_i)
            std::fprintf(f, "%.9g %.9g %.9g %.9g\n", p.x(), p.y(), p.z(), c.intensity[i]);
        else
            std::fprintf(f, "%.9g %.9g %.9g\n", p.x(), p.y(), p.z());
    }
    const bool ok = std::ferror(f) == 0;
    if (std::fclose(f) != 0 || !ok) throw std::runtime_error(path + ": write error");
}

}  // namespace detail
}  // namespace superloc::io
