// Tiled prior maps: the tile files and index (io/map_tiles.h) and the tiles loaded around a
// point (map::TiledMap), with the one-line errors of a bad index.
#include <superloc/io/map_tiles.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/map/tiled_map.h>
#include <superloc_testing/testing.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>

using namespace superloc;

namespace {
/// Points on a 100 m x 60 m ground with normals, plus a few on walls.
PointCloud ground() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> X(-40.f, 60.f), Y(-30.f, 30.f);
    PointCloud c;
    for (int i = 0; i < 20000; ++i) {
        c.points.emplace_back(X(rng), Y(rng), 0.f);
        c.normals.emplace_back(0.f, 0.f, 1.f);
    }
    return c;
}

void writeIndex(const std::string& dir, const std::string& text) {
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/tiles.csv") << text;
}

std::string errorOf(const std::string& dir) {
    try {
        io::readMapTileIndex(dir);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(MapTiles, RoundTripKeepsEveryPointInItsTile) {
    const PointCloud c = ground();
    const std::string dir = superloc::testing::freshDir("map_tiles_round_trip");
    const io::MapTileIndex w = io::writeMapTiles(c, 10.0, dir);
    EXPECT_EQ(w.tiles.size(), 60u);  // 10 x 6 tiles of 10 m
    EXPECT_EQ(w.totalPoints(), c.size());
    EXPECT_TRUE(io::isMapTileDir(dir));
    EXPECT_FALSE(io::isMapTileDir(dir + "/tiles.csv"));
    const io::MapTileIndex r = io::readMapTileIndex(dir);
    EXPECT_DOUBLE_EQ(r.tile_size, 10.0);
    ASSERT_EQ(r.tiles.size(), w.tiles.size());
    size_t total = 0;
    for (const io::MapTile& t : r.tiles) {
        const PointCloud tile = io::loadPointCloud(t.file);
        ASSERT_EQ(tile.size(), t.points) << t.file;
        ASSERT_EQ(tile.normals.size(), tile.size()) << "normals kept";
        for (const Vec3f& p : tile.points) {
            ASSERT_EQ(static_cast<int64_t>(std::floor(p.x() / 10.0)), t.ix);
            ASSERT_EQ(static_cast<int64_t>(std::floor(p.y() / 10.0)), t.iy);
        }
        total += tile.size();
    }
    EXPECT_EQ(total, c.size());
    EXPECT_THROW(io::writeMapTiles(c, 0.0, dir), std::invalid_argument);
}

TEST(MapTiles, TiledMapLoadsTheTilesWithinTheRadius) {
    const PointCloud c = ground();
    const std::string dir = superloc::testing::freshDir("map_tiles_around");
    io::writeMapTiles(c, 10.0, dir);
    map::MapParams p;
    p.voxel_size = 0;
    map::TiledMap tiles(dir, p, 15.0);
    const auto m = tiles.loadAround(Vec3d(5, 5, 0));
    // Tiles whose square is within 15 m of (5, 5), which lies in tile (0, 0): the 3 x 3 around it
    // (at most 5 m away per axis, 7.1 m diagonally) and the four 2 tiles away along an axis
    // (exactly 15 m); not (1, 2) and the like (sqrt(5^2 + 15^2) = 15.8 m).
    EXPECT_EQ(tiles.tilesLoaded(), 13u);
    EXPECT_EQ(m->size(), tiles.pointsLoaded());
    size_t expected = 0;
    for (const Vec3f& q : c.points) {
        const double dx = std::max({std::floor(q.x() / 10.0) * 10 - 5, 0.0, 5 - (std::floor(q.x() / 10.0) * 10 + 10)});
        const double dy = std::max({std::floor(q.y() / 10.0) * 10 - 5, 0.0, 5 - (std::floor(q.y() / 10.0) * 10 + 10)});
        expected += dx * dx + dy * dy <= 15.0 * 15.0;
    }
    EXPECT_EQ(m->size(), expected);
    // The file's normals orient the geometry (+z).
    EXPECT_TRUE(m->geometry(0).oriented);
    EXPECT_GT(m->geometry(0).normal.z(), 0.99f);
    EXPECT_EQ(tiles.loadAround(Vec3d(500, 500, 0))->size(), 0u);
    EXPECT_EQ(tiles.tilesLoaded(), 0u);
}

TEST(MapTiles, BadIndexIsAOneLineErrorNamingFileAndLine) {
    const std::string base = superloc::testing::freshDir("map_tiles_bad");
    EXPECT_NE(errorOf(base + "/none").find("tiles.csv: cannot open"), std::string::npos);
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"tile_size,abc\nix,iy,points,file\n", "tiles.csv:1: tile_size must be a number > 0"},
        {"tile_size,-5\n", "tiles.csv:1: tile_size must be a number > 0"},
        {"# c\ntile_size,10\nx,y\n", "tiles.csv:3: expected the header"},
        {"tile_size,10\nix,iy,points,file\n1,2,three,t.pcd\n", "tiles.csv:3: ix, iy and points must be integers"},
        {"tile_size,10\nix,iy,points,file\n1,2,3,../t.pcd\n", "tiles.csv:3: the file must be a plain file name"},
        {"tile_size,10\nix,iy,points,file\n1,2,3,missing.pcd\n", "tiles.csv:3: missing.pcd: tile file not found"},
        {"", "tiles.csv:0: no `tile_size` line"},
    };
    int k = 0;
    for (const auto& [text, want] : cases) {
        const std::string dir = base + "/case" + std::to_string(k++);
        writeIndex(dir, text);
        const std::string e = errorOf(dir);
        EXPECT_NE(e.find(want), std::string::npos) << "got: " << e;
        EXPECT_EQ(e.find('\n'), std::string::npos);
    }
}
