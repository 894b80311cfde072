// Tiled prior maps on disk: tiles.csv and one binary PCD per non-empty tile.
#include <superloc/core/config.h>
#include <superloc/core/voxel.h>
#include <superloc/io/map_tiles.h>
#include <superloc/io/point_cloud_io.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace superloc::io {

namespace fs = std::filesystem;

namespace {
constexpr const char* kIndexName = "tiles.csv";

std::string tileName(int64_t ix, int64_t iy) {
    return "tile_" + std::to_string(ix) + "_" + std::to_string(iy) + ".pcd";
}
}  // namespace

size_t MapTileIndex::totalPoints() const {
    size_t n = 0;
    for (const MapTile& t : tiles) n += t.points;
    return n;
}

MapTileIndex writeMapTiles(const PointCloud& cloud, double tile_size, const std::string& dir) {
    if (!std::isfinite(tile_size) || tile_size <= 0)
        throw std::invalid_argument("map tiles: tile size must be > 0 m, got " + std::to_string(tile_size));
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir)) throw std::runtime_error(dir + ": cannot create the tile directory");
    std::map<std::pair<int64_t, int64_t>, std::vector<uint32_t>> members;
    for (uint32_t i = 0; i < cloud.size(); ++i) {
        const Vec3f& p = cloud.points[i];
        if (!p.allFinite()) continue;
        const double fx = std::floor(static_cast<double>(p.x()) / tile_size);
        const double fy = std::floor(static_cast<double>(p.y()) / tile_size);
        if (std::abs(fx) > 1e15 || std::abs(fy) > 1e15) continue;
        members[{static_cast<int64_t>(fx), static_cast<int64_t>(fy)}].push_back(i);
    }
    MapTileIndex index;
    index.dir = dir;
    index.tile_size = tile_size;
    const std::string index_path = (fs::path(dir) / kIndexName).string();
    std::ofstream out(index_path);
    if (!out) throw std::runtime_error(index_path + ": cannot write");
    out.precision(17);
    out << "# superloc map tiles: tile (ix, iy) holds the points with floor(x/s) = ix, floor(y/s) = iy\n"
        << "tile_size," << tile_size << "\nix,iy,points,file\n";
    for (const auto& [key, idx] : members) {
        MapTile t;
        t.ix = key.first;
        t.iy = key.second;
        t.points = idx.size();
        const std::string name = tileName(t.ix, t.iy);
        t.file = (fs::path(dir) / name).string();
        savePointCloud(t.file, selectIndices(cloud, idx), CloudFormat::PcdBinary);
        out << t.ix << ',' << t.iy << ',' << t.points << ',' << name << '\n';
        index.tiles.push_back(std::move(t));
    }
    out.flush();
    if (!out) throw std::runtime_error(index_path + ": write failed");
    return index;
}

MapTileIndex readMapTileIndex(const std::string& dir) {
    const std::string path = (fs::path(dir) / kIndexName).string();
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open the map tile index");
    MapTileIndex index;
    index.dir = dir;
    std::string line;
    size_t line_no = 0;
    bool have_size = false, have_header = false;
    const auto fail = [&](const std::string& why) {
        throw std::runtime_error(path + ":" + std::to_string(line_no) + ": " + why);
    };
    while (std::getline(in, line)) {
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
        if (!have_size) {
            if (f.size() != 2 || f[0] != "tile_size") fail("expected `tile_size,METRES`");
            if (!parseDouble(f[1], index.tile_size) || index.tile_size <= 0) fail("tile_size must be a number > 0");
            have_size = true;
            continue;
        }
        if (!have_header) {
            if (line != "ix,iy,points,file") fail("expected the header `ix,iy,points,file`");
            have_header = true;
            continue;
        }
        if (f.size() != 4) fail("expected `ix,iy,points,file`");
        MapTile t;
        try {
            size_t a = 0, b = 0, c = 0;
            t.ix = std::stoll(f[0], &a);
            t.iy = std::stoll(f[1], &b);
            const long long n = std::stoll(f[2], &c);
            if (a != f[0].size() || b != f[1].size() || c != f[2].size() || n < 0) throw std::invalid_argument("");
            t.points = static_cast<size_t>(n);
        } catch (const std::exception&) {
            fail("ix, iy and points must be integers (points >= 0)");
        }
        if (f[3].empty() || f[3].find('/') != std::string::npos || f[3].find('\\') != std::string::npos)
            fail("the file must be a plain file name in the tile directory");
        t.file = (fs::path(dir) / f[3]).string();
        if (!fs::exists(t.file)) fail(f[3] + ": tile file not found");
        index.tiles.push_back(std::move(t));
    }
    if (!have_size || !have_header) {
        line_no = 0;
        fail("no `tile_size` line and `ix,iy,points,file` header");
    }
    return index;
}

bool isMapTileDir(const std::string& path) {
    std::error_code ec;
    return fs::is_directory(path, ec) && fs::exists(fs::path(path) / kIndexName, ec);
}

}  // namespace superloc::io
