// MRPT map files as prior maps: a .simplemap written by MRPT's own API (CSimpleMap::saveToFile)
// from real KITTI scans, and serialized point maps (.pointsmap).
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>
#include <superloc/core/mrpt_conversions.h>
#include <superloc/core/se3.h>
#include <superloc/io/importers.h>
#include <superloc/io/mrpt_maps.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>
#include <superloc/map/map_builder.h>
#include <superloc/map/prior_map.h>
#include <superloc_testing/testing.h>

#include <fstream>

namespace {

using namespace superloc;

const SE3d kT_base_velodyne = makePoseRPY(0.27, 0, 1.73, 0, 0, 1.5 * M_PI / 180);
constexpr size_t kScans = 4;

std::string kittiBin(size_t i) {
    char name[64];
    std::snprintf(name, sizeof(name), "kitti00-mini/velodyne/%06zu.bin", i);
    return superloc::testing::sharedData(name);
}

/// The first kScans KITTI scans as an MRPT simplemap, written by MRPT's API: one keyframe per
/// scan at the base_link pose (gt_velodyne_tum * T_base_velodyne^-1, as a Gaussian PDF), a
/// CObservationPointCloud (CPointsMapXYZI read by MRPT's KITTI loader) with sensorPose
/// T_base_velodyne.
void writeSimpleMap(const std::string& path) {
    const auto gt = io::loadTum(superloc::testing::sharedData("kitti00-mini/gt_velodyne_tum.txt"));
    mrpt::maps::CSimpleMap sm;
    for (size_t i = 0; i < kScans; ++i) {
        auto pc = mrpt::maps::CPointsMapXYZI::Create();
        ASSERT_TRUE(pc->loadFromKittiVelodyneFile(kittiBin(i)));
        auto obs = mrpt::obs::CObservationPointCloud::Create();
        obs->pointcloud = pc;
        obs->sensorLabel = "lidar";
        obs->sensorPose = toMrpt(kT_base_velodyne);
        obs->timestamp = mrpt::Clock::fromDouble(gt[i].t);
        mrpt::obs::CSensoryFrame sf;
        sf.insert(obs);
        sm.insert(mrpt::poses::CPose3DPDFGaussian(toMrpt(gt[i].pose * kT_base_velodyne.inverse())),
                  sf);
    }
    ASSERT_TRUE(sm.saveToFile(path));
}

}  // namespace

TEST(MrptMaps, SimpleMapLoadsEveryScanAtItsKeyframePose) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("mrpt_simplemap_load");
    writeSimpleMap(dir + "/k.simplemap");
    io::SimpleMapStats st;
    const PointCloud c = io::loadSimpleMap(dir + "/k.simplemap", &st);
    EXPECT_EQ(st.keyframes, kScans);
    EXPECT_EQ(st.scans, kScans);
    const auto gt = io::loadTum(superloc::testing::sharedData("kitti00-mini/gt_velodyne_tum.txt"));
    size_t k = 0;
    double max_err = 0;
    for (size_t i = 0; i < kScans; ++i) {
        const PointCloud scan = io::loadPointCloud(kittiBin(i));
        for (size_t j = 0; j < scan.size(); ++j, ++k) {
            ASSERT_LT(k, c.size());
            const Vec3d want = gt[i].pose * scan.points[j].cast<double>();
            max_err = std::max(max_err, (c.points[k].cast<double>() - want).norm());
            ASSERT_EQ(c.intensity[k], scan.intensity[j]);
        }
    }
    EXPECT_EQ(k, c.size());
    std::cout << "[ simplemap ] " << c.size() << " points from " << kScans
              << " keyframes, max |p - T_map_velodyne p_scan| = " << max_err << " m\n";
    EXPECT_LT(max_err, 1e-4);  // float map coordinates ~100 m from the origin
    // io::loadPointCloud and PriorMap::load (superloc-localize --map) take it by extension.
    EXPECT_EQ(io::loadPointCloud(dir + "/k.simplemap").size(), c.size());
    map::MapParams mp;
    mp.voxel_size = 0.5;
    mp.normal_max_radius = 2.0;
    EXPECT_GT(map::PriorMap::load(dir + "/k.simplemap", mp).size(), 10000u);
}

TEST(MrptMaps, MapFromSimpleMapEqualsMapFromRawlog) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("mrpt_simplemap_builder");
    writeSimpleMap(dir + "/k.simplemap");
    const auto kitti = superloc::testing::sharedData("kitti00-mini");
    io::importKitti(kitti, kitti + "/gt_velodyne_tum.txt", "", dir + "/k.rawlog");
    map::MapBuildOptions a;
    a.simplemap = dir + "/k.simplemap";
    a.voxel = 0;
    a.normals = false;
    map::MapBuildOptions b = a;
    b.simplemap.clear();
    b.rawlog = dir + "/k.rawlog";
    b.rawlog_params.scans = "0:" + std::to_string(kScans);
    const PointCloud ma = map::MapBuilder(a).build(), mb = map::MapBuilder(b).build();
    ASSERT_EQ(ma.size(), mb.size());
    double max_d = 0;
    for (size_t i = 0; i < ma.size(); ++i)
        max_d = std::max(max_d, double((ma.points[i] - mb.points[i]).norm()));
    std::cout << "[ simplemap ] superloc-map --simplemap vs --rawlog (gt poses): " << ma.size()
              << " points, max difference " << max_d << " m\n";
    EXPECT_LT(max_d, 1e-4);
}

TEST(MrptMaps, PointsMapFilesBothWays) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("mrpt_pointsmap");
    // Written by MRPT's own serialization, read by io::loadPointCloud: exact.
    mrpt::maps::CPointsMapXYZI m;
    ASSERT_TRUE(m.loadFromKittiVelodyneFile(kittiBin(0)));
    {
        mrpt::io::CFileGZOutputStream f(dir + "/mrpt.pointsmap");
        mrpt::serialization::archiveFrom(f) << m;
    }
    const PointCloud c = io::loadPointCloud(dir + "/mrpt.pointsmap");
    ASSERT_EQ(c.size(), m.size());
    ASSERT_EQ(c.intensity.size(), m.size());
    for (size_t i = 0; i < m.size(); ++i) {
        ASSERT_EQ(c.points[i], Vec3f(m.getPointsBufferRef_x()[i], m.getPointsBufferRef_y()[i],
                                     m.getPointsBufferRef_z()[i]));
        ASSERT_EQ(c.intensity[i], m.getPointIntensity(i));
    }
    // Written by io::savePointCloud, read by MRPT: exact.
    io::savePointCloud(dir + "/ours.pointsmap", c);
    mrpt::io::CFileGZInputStream f(dir + "/ours.pointsmap");
    const auto obj = mrpt::serialization::archiveFrom(f).ReadObject();
    const auto back = std::dynamic_pointer_cast<mrpt::maps::CPointsMapXYZI>(obj);
    ASSERT_TRUE(back);
    ASSERT_EQ(back->size(), c.size());
    for (size_t i = 0; i < c.size(); ++i) {
        ASSERT_EQ(back->getPointsBufferRef_x()[i], c.points[i].x());
        ASSERT_EQ(back->getPointIntensity(i), c.intensity[i]);
    }
    // Bad input: one line naming the file.
    std::ofstream(dir + "/text.simplemap") << "not a simplemap\n";
    std::ofstream(dir + "/text.pointsmap") << "not a point map\n";
    writeSimpleMap(dir + "/k.simplemap");
    std::filesystem::copy_file(dir + "/k.simplemap", dir + "/sm.pointsmap");
    for (const std::string f : {"text.simplemap", "text.pointsmap", "sm.pointsmap"}) {
        std::string e;
        try {
            io::loadPointCloud(dir + "/" + f);
        } catch (const std::exception& x) {
            e = x.what();
        }
        EXPECT_EQ(e.rfind(dir + "/" + f + ": ", 0), 0u) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
        if (f == "sm.pointsmap") {
            EXPECT_NE(e.find("CSimpleMap, not a point map"), std::string::npos) << e;
        }
    }
}

// The apps: superloc-map --simplemap, and superloc-localize --map X.simplemap localizing the
// same 4 KITTI scans (a circular sanity check: the map holds those scans, doc/design.md#8-evaluation).
TEST(MrptMaps, AppsTakeASimpleMap) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const std::string map_exe = superloc::testing::appPath("superloc-map");
    const std::string loc_exe = superloc::testing::appPath("superloc-localize");
    if (!std::filesystem::exists(map_exe) || !std::filesystem::exists(loc_exe))
        GTEST_SKIP() << "superloc-map / superloc-localize not built";
    const auto dir = superloc::testing::freshDir("mrpt_simplemap_apps");
    writeSimpleMap(dir + "/k.simplemap");
    const auto kitti = superloc::testing::sharedData("kitti00-mini");
    const auto run = [&](const std::string& cmd) {
        return std::system((cmd + " > " + dir + "/out.txt 2> " + dir + "/err.txt").c_str());
    };
    ASSERT_EQ(run(map_exe + " --simplemap " + dir + "/k.simplemap --voxel 0.2 --no-normals --out " +
                  dir + "/m.pcd"),
              0);
    EXPECT_GT(io::loadPointCloud(dir + "/m.pcd").size(), 50000u);
    EXPECT_NE(run(map_exe + " --simplemap " + dir + "/k.simplemap --out " + dir + "/m.simplemap"),
              0);
    io::importKitti(kitti, "", "", dir + "/k.rawlog");
    ASSERT_EQ(
        run(loc_exe + " " + superloc::testing::sourcePath("ini/localize-kitti.ini") + " --rawlog " +
            dir + "/k.rawlog --map " + dir + "/k.simplemap" + " --initial-pose-tum " + kitti +
            "/gt_velodyne_tum.txt --set rawlog.scans=0:4" + " --out " + dir + "/run --quiet"),
        0);
    const auto est = io::loadTum(dir + "/run/trajectory.tum");
    const auto gt = io::loadTum(kitti + "/gt_velodyne_tum.txt");
    ASSERT_EQ(est.size(), kScans);
    double max_err = 0;
    for (size_t i = 0; i < kScans; ++i)
        max_err = std::max(max_err, translationDistance(est[i].pose, gt[i].pose));
    std::cout << "[ simplemap ] superloc-localize --map k.simplemap: max error " << max_err
              << " m over " << kScans << " scans\n";
    EXPECT_LT(max_err, 0.1);
}
