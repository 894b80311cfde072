// MapParams: INI load/save/validate and PriorMap::load errors.
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>
#include <superloc/map/prior_map.h>
#include <superloc_testing/testing.h>

using namespace superloc;
using namespace superloc::map;

TEST(MapParams, SaveLoadRoundTrip) {
    MapParams p;
    p.voxel_size = 0.25;
    p.normal_k = 17;
    p.normal_max_radius = 2.5;
    mrpt::config::CConfigFileMemory cfg;
    p.saveToConfigFile(cfg, "map");
    // Through the text form, as a saved INI file is read back (padded keys, comments).
    const mrpt::config::CConfigFileMemory text(cfg.getContent());
    const auto q = loadParams<MapParams>(text, "map", "test.ini");
    EXPECT_DOUBLE_EQ(q.voxel_size, 0.25);
    EXPECT_EQ(q.normal_k, 17);
    EXPECT_DOUBLE_EQ(q.normal_max_radius, 2.5);
}

TEST(MapParams, BadIniIsAOneLineError) {
    mrpt::config::CConfigFileMemory unknown;
    unknown.write("map", "voxelsize", "0.1");
    EXPECT_THROW(loadParams<MapParams>(unknown, "map", "x.ini"), ConfigError);

    mrpt::config::CConfigFileMemory wrong_type;
    wrong_type.write("map", "normal_k", "ten");
    try {
        loadParams<MapParams>(wrong_type, "map", "x.ini");
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("x.ini"), std::string::npos) << msg;
        EXPECT_NE(msg.find("normal_k"), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }

    for (const char* bad : {"k=2", "voxel=-1", "radius=0"}) {
        MapParams p;
        if (std::string(bad) == "k=2") p.normal_k = 2;
        if (std::string(bad) == "voxel=-1") p.voxel_size = -1;
        if (std::string(bad) == "radius=0") p.normal_max_radius = 0;
        EXPECT_THROW(p.validate(), ConfigError) << bad;
    }
}

TEST(PriorMapLoad, MissingFileNamesTheFile) {
    try {
        PriorMap::load("/nonexistent/map.pcd", MapParams{});
        FAIL() << "no error";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/map.pcd"), std::string::npos);
    }
}

TEST(PriorMapLoad, LoadsARealScanFromPcd) {
    SUPERLOC_REQUIRE_DATA("scan-pair-outdoor/251370668.pcd");
    MapParams p;
    p.voxel_size = 0.2;
    const PriorMap map = PriorMap::load(superloc::testing::sharedData("scan-pair-outdoor/251370668.pcd"), p);
    EXPECT_GT(map.size(), 5000u);
    EXPECT_LT(map.size(), 69000u);
    size_t with_normal = 0;
    for (size_t i = 0; i < map.size(); ++i)
        with_normal += map.geometry(i).normal.squaredNorm() > 0.99f ? 1 : 0;
    EXPECT_GT(with_normal, map.size() * 9 / 10);
}
