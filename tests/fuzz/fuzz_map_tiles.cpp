// libFuzzer target: io::readMapTileIndex on a tiles.csv (doc/map.md "Tiled maps"), then every
// tile it lists read with io::loadPointCloud. The scratch directory holds one small valid tile
// (`t.pcd`) so that indexes naming it get past the file check.
#include <superloc/io/map_tiles.h>

#include <cmath>
#include <filesystem>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string dir = [] {
        const std::string d = superloc::fuzz::scratchPath(".tiles");
        std::filesystem::create_directories(d);
        superloc::PointCloud c;
        c.points = {superloc::Vec3f(1, 2, 3), superloc::Vec3f(4, 5, 6)};
        superloc::io::savePointCloud(d + "/t.pcd", c);
        return d;
    }();
    superloc::fuzz::writeBytes(dir + "/tiles.csv", data, size);
    superloc::fuzz::expectLoadsOrThrowsOneLine([&] {
        const superloc::io::MapTileIndex index = superloc::io::readMapTileIndex(dir);
        if (!(index.tile_size > 0) || !std::isfinite(index.tile_size)) std::abort();
        for (const auto& t : index.tiles) {
            if (std::filesystem::path(t.file).parent_path() != std::filesystem::path(dir)) std::abort();
            superloc::io::loadPointCloud(t.file);
        }
    });
    return 0;
}
