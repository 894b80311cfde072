// superloc-map on real data: a campus-ouster subset imported as a rawlog and mapped with its
// ground-truth poses gives sharp surfaces; the same scans at perturbed poses do not.
#include <superloc/core/se3.h>
#include <superloc/io/importers.h>
#include <superloc/io/tum.h>
#include <superloc/app/command_line.h>
#include <superloc/app/map_app.h>
#include <superloc/map/map_builder.h>
#include <superloc/map/prior_map.h>
#include <superloc_testing/testing.h>

#include <filesystem>
#include <random>

using namespace superloc;
namespace fs = std::filesystem;

namespace {

constexpr size_t kFirst = 8, kCount = 12;  // scans 8..19: the walk after the stationary start

struct Campus {
    std::string dir, rawlog, tum;
    Trajectory gt;
};

const Campus& campusSubset() {
    static const Campus c = [] {
        Campus c;
        c.dir = superloc::testing::freshDir("map_real_campus");
        const fs::path scans = superloc::testing::sharedData("campus-ouster/scans");
        std::vector<fs::path> files;
        for (const auto& e : fs::directory_iterator(scans)) files.push_back(e.path());
        std::sort(files.begin(), files.end());
        const Trajectory all = io::loadTum(superloc::testing::sharedData("campus-ouster/gt_tum.txt"));
        fs::create_directories(c.dir + "/scans");
        for (size_t i = kFirst; i < kFirst + kCount; ++i) {
            fs::create_symlink(files.at(i), c.dir + "/scans/" + files[i].filename().string());
            c.gt.push_back(all.at(i));
        }
        c.tum = c.dir + "/gt.tum";
        io::saveTum(c.tum, c.gt);
        c.rawlog = c.dir + "/campus.rawlog";
        io::importPcdFolder(c.dir + "/scans", c.tum, "", c.rawlog);
        return c;
    }();
    return c;
}

map::MapStats statsWithPoses(const Campus& c, const std::string& tum, size_t* points = nullptr) {
    map::MapBuildOptions o;
    o.rawlog = c.rawlog;
    o.poses_tum = tum;
    o.voxel = 0.1;
    map::MapBuilder b(o);
    const PointCloud m = b.build();
    EXPECT_EQ(b.result().scans_used, kCount);
    if (points) *points = m.size();
    map::MapParams p;
    return map::computeMapStats(m, p);
}

}  // namespace

TEST(MapReal, CampusWallsAreSharpWithGroundTruthPoses) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const Campus& c = campusSubset();
    size_t n = 0;
    const map::MapStats gt = statsWithPoses(c, "", &n);  // the rawlog's gt poses
    EXPECT_GT(n, 50000u);
    EXPECT_GT(gt.planar_fraction, 0.25);
    EXPECT_LT(gt.median_planar_fit_residual, 0.025);  // measured: see doc/io.md

    // Every pose moved by ~5 cm: surfaces seen from several places double up and thicken.
    Trajectory noisy = c.gt;
    std::mt19937 rng(1);
    std::normal_distribution<double> g(0.0, 0.05);
    for (auto& p : noisy) p.pose.translation() += Vec3d(g(rng), g(rng), g(rng));
    const std::string noisy_tum = c.dir + "/noisy.tum";
    io::saveTum(noisy_tum, noisy);
    const map::MapStats bad = statsWithPoses(c, noisy_tum);
    EXPECT_GT(bad.median_planar_fit_residual, 1.3 * gt.median_planar_fit_residual);
}

TEST(MapReal, PriorMapFromTheBuiltMapHasNormalsAlmostEverywhere) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/gt_tum.txt");
    const Campus& c = campusSubset();
    const std::string out = c.dir + "/map.pcd";
    std::vector<const char*> argv = {"superloc-map", "--rawlog", c.rawlog.c_str(), "--out",
                                     out.c_str()};
    app::MapApp(app::parseMapAppArgs(app::argList(static_cast<int>(argv.size()), argv.data()))).run();
    map::MapParams p;
    p.voxel_size = 0.2;
    const map::PriorMap m = map::PriorMap::load(out, p);
    size_t ok = 0;
    for (size_t i = 0; i < m.size(); ++i) ok += m.geometry(i).normal.squaredNorm() > 0.99f ? 1 : 0;
    EXPECT_GT(ok, m.size() * 95 / 100);
}
