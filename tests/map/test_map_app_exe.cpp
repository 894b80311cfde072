// The superloc-map executable itself: exit codes and one-line errors on stderr.
#include <superloc_testing/testing.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

const std::string kExe = superloc::testing::appPath("superloc-map");

struct ExeResult {
    int code;
    std::string err;
};

ExeResult runExe(const std::string& args) {
    const std::string dir = superloc::testing::freshDir("map_app_exe");
    const std::string err = dir + "/stderr.txt";
    const int rc = std::system((kExe + " " + args + " > " + dir + "/stdout.txt 2> " + err).c_str());
    std::ifstream in(err);
    std::stringstream ss;
    ss << in.rdbuf();
    return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str()};
}

}  // namespace

TEST(SuperlocMapExe, HelpAndBadInput) {
    if (!std::filesystem::exists(kExe)) GTEST_SKIP() << "superloc-map not built: " << kExe;
    EXPECT_EQ(runExe("--help").code, 0);
    const std::string bad_rawlog = superloc::testing::freshDir("map_app_exe_input") + "/bad.rawlog";
    std::ofstream(bad_rawlog) << "this is not a rawlog";
    for (const std::string& args :
         {std::string("--rawlog /nonexistent.rawlog --out m.pcd"), std::string("--frobnicate"),
          std::string("--rawlog ") + bad_rawlog + " --out m.pcd"}) {
        const ExeResult r = runExe(args);
        EXPECT_NE(r.code, 0) << args;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
        EXPECT_EQ(r.err.rfind("superloc-map: ", 0), 0u) << r.err;
    }
}

TEST(SuperlocMapExe, SplitsAMapIntoTiles) {
    if (!std::filesystem::exists(kExe)) GTEST_SKIP() << "superloc-map not built: " << kExe;
    const std::string scan = superloc::testing::sharedData("campus-ouster/scans/0000.pcd");
    if (!std::filesystem::exists(scan)) GTEST_SKIP() << "no shared data";
    const std::string dir = superloc::testing::freshDir("map_app_exe_tiles");
    const ExeResult ok = runExe("--from-map " + scan + " --tile-size 10 --out " + dir + "/tiles");
    ASSERT_EQ(ok.code, 0) << ok.err;
    EXPECT_TRUE(std::filesystem::exists(dir + "/tiles/tiles.csv"));
    EXPECT_TRUE(std::filesystem::exists(dir + "/tiles/tile_0_0.pcd"));
    std::ofstream(dir + "/a_file") << "x";
    for (const std::string& args :
         {"--from-map " + scan + " --tile-size -1 --out " + dir + "/t2",
          "--from-map " + scan + " --tile-size 10 --out " + dir + "/a_file",
          "--from-map /nonexistent.pcd --out " + dir + "/m.pcd",
          "--from-map " + scan + " --rawlog x.rawlog --out " + dir + "/m.pcd"}) {
        const ExeResult r = runExe(args);
        EXPECT_NE(r.code, 0) << args;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    }
}
