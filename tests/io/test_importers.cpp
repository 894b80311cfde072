// Importers on the real data sets: scan count, point counts, times and poses equal the inputs.
#include <superloc/core/se3.h>
#include <superloc/io/importers.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/tum.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace superloc;
using namespace superloc::io;
using superloc::testing::freshDir;
using superloc::testing::sharedData;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> sorted(const std::string& dir, const std::string& ext) {
    std::vector<std::string> f;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ext) f.push_back(e.path().string());
    std::sort(f.begin(), f.end());
    return f;
}

/// Reads the rawlog back and checks it against the scan files, the times and the poses.
void checkImport(const std::string& rawlog, const std::vector<std::string>& files,
                 const std::vector<double>& times, const Trajectory& poses) {
    RawlogReader r(rawlog);
    RawlogItem it;
    std::vector<Scan> scans;
    Trajectory gt;
    while (r.next(it)) {
        if (it.kind == RawlogItem::Kind::Lidar) scans.push_back(it.scan());
        if (it.kind == RawlogItem::Kind::GroundTruth) gt.push_back(it.pose());
    }
    ASSERT_EQ(scans.size(), files.size());
    ASSERT_EQ(gt.size(), poses.size());
    for (size_t i = 0; i < files.size(); ++i) {
        const PointCloud c = loadPointCloud(files[i]);
        ASSERT_EQ(scans[i].size(), c.size()) << files[i];
        EXPECT_LT((scans[i].points.back() - c.points.back()).norm(), 1e-6f);
        ASSERT_EQ(scans[i].intensity.size(), c.size());
        EXPECT_NEAR(scans[i].t, times[i], 1e-6) << i;
    }
    for (size_t i = 0; i < poses.size(); ++i) {
        EXPECT_NEAR(gt[i].t, times[i], 1e-6);
        EXPECT_LT(translationDistance(gt[i].pose, poses[i].pose), 1e-9) << i;
        EXPECT_LT(rotationAngle(gt[i].pose, poses[i].pose), 1e-9) << i;
    }
}

void expectImportError(const std::function<void()>& f, const std::string& fragment) {
    try {
        f();
        ADD_FAILURE() << "no error, expected '" << fragment << "'";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
}

}  // namespace

TEST(Importers, KittiMini) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = sharedData("kitti00-mini");
    const auto out = freshDir("import_kitti") + "/kitti.rawlog";
    size_t calls = 0;
    const auto r =
        importKitti(dir, dir + "/gt_velodyne_tum.txt", "", out, [&](size_t done, size_t total) {
            ++calls;
            EXPECT_LE(done, total);
        });
    EXPECT_EQ(r.scans, 16u);
    EXPECT_EQ(r.gt_poses, 16u);
    EXPECT_EQ(calls, 16u);
    const auto files = sorted(dir + "/velodyne", ".bin");
    size_t points = 0;
    for (const auto& f : files) points += fs::file_size(f) / 16;
    EXPECT_EQ(r.points, points);
    std::vector<double> times;
    std::ifstream tin(dir + "/times.txt");
    for (double t; tin >> t;) times.push_back(t);
    checkImport(out, files, times, loadTum(dir + "/gt_velodyne_tum.txt"));
}

TEST(Importers, CampusOusterPcdFolder) {
    SUPERLOC_REQUIRE_DATA("campus-ouster");
    const auto dir = sharedData("campus-ouster");
    const auto out = freshDir("import_campus") + "/campus.rawlog";
    const auto r = importPcdFolder(dir + "/scans", dir + "/gt_tum.txt", "", out);
    EXPECT_EQ(r.scans, 53u);
    EXPECT_EQ(r.gt_poses, 53u);
    const auto poses = loadTum(dir + "/gt_tum.txt");
    std::vector<double> times;
    for (const auto& p : poses) times.push_back(p.t);
    checkImport(out, sorted(dir + "/scans", ".pcd"), times, poses);
}

TEST(Importers, BadInputsGiveOneLineErrors) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = sharedData("kitti00-mini");
    const auto tmp = freshDir("import_bad");
    const auto out = tmp + "/x.rawlog";
    expectImportError([&] { importKitti(tmp + "/none", "", "", out); },
                      "none/velodyne: folder not found");
    fs::create_directories(tmp + "/empty/velodyne");
    expectImportError([&] { importKitti(tmp + "/empty", "", "", out); }, "no *.bin files");
    std::ofstream(tmp + "/short_times.txt") << "0\n0.1\n";
    expectImportError([&] { importKitti(dir, "", tmp + "/short_times.txt", out); },
                      "short_times.txt: 2 entries for 16 scans");
    std::ofstream(tmp + "/back_times.txt") << "0\n0.2\n0.1\n";
    expectImportError([&] { importKitti(dir, "", tmp + "/back_times.txt", out); },
                      "back_times.txt:3: time does not increase");
    std::ofstream(tmp + "/word_times.txt") << "0\nsoon\n";
    expectImportError([&] { importKitti(dir, "", tmp + "/word_times.txt", out); },
                      "word_times.txt:2: not a time");
    std::ofstream(tmp + "/far.tum") << "100 0 0 0 0 0 0 1\n200 0 0 0 0 0 0 1\n";
    expectImportError([&] { importKitti(dir, tmp + "/far.tum", "", out); }, "no timestamp matches");
    expectImportError([&] { importPcdFolder(dir + "/velodyne", "", "", out); }, "no *.pcd files");
    fs::create_directories(tmp + "/pcds");
    savePointCloud(tmp + "/pcds/0.pcd", loadPointCloud(dir + "/velodyne/000000.bin"));
    expectImportError([&] { importPcdFolder(tmp + "/pcds", "", "", out); },
                      "needs --poses TUM or --times");
    std::ofstream(tmp + "/pcds/1.pcd") << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\n";  // corrupt
    std::ofstream(tmp + "/two_times.txt") << "0\n0.1\n";
    expectImportError([&] { importPcdFolder(tmp + "/pcds", "", tmp + "/two_times.txt", out); },
                      "1.pcd");
}

// Issue 36: a scan file with no valid point (empty, or all NaN) is not written as a scan (the
// reader would skip it); it is counted, with the first such file named, for the app's warning.
TEST(Importers, EmptyScansAreCountedNotWritten) {
    const auto tmp = freshDir("import_empty_scans");
    fs::create_directories(tmp + "/k/velodyne");
    const float p[4] = {1, 2, 3, 0.5f}, nan[4] = {NAN, 0, 0, 0};
    std::ofstream(tmp + "/k/velodyne/000000.bin", std::ios::binary).write(reinterpret_cast<const char*>(p), 16);
    std::ofstream(tmp + "/k/velodyne/000001.bin", std::ios::binary);  // empty
    std::ofstream(tmp + "/k/velodyne/000002.bin", std::ios::binary).write(reinterpret_cast<const char*>(nan), 16);
    std::ofstream(tmp + "/k/velodyne/000003.bin", std::ios::binary).write(reinterpret_cast<const char*>(p), 16);
    std::ofstream(tmp + "/k/times.txt") << "0\n0.1\n0.2\n0.3\n";
    const ImportResult r = importKitti(tmp + "/k", "", "", tmp + "/o.rawlog");
    EXPECT_EQ(r.scans, 2u);
    EXPECT_EQ(r.empty_scans, 2u);
    EXPECT_EQ(r.dropped_points, 1u);
    EXPECT_NE(r.first_empty.find("000001.bin"), std::string::npos) << r.first_empty;
    RawlogReader reader(tmp + "/o.rawlog");
    RawlogItem it;
    std::vector<double> t;
    while (reader.next(it)) t.push_back(it.time());
    EXPECT_EQ(t, (std::vector<double>{0.0, 0.3}));
    EXPECT_EQ(reader.stats().empty_scans, 0u);
}
