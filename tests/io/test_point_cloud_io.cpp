// PCD (binary/ASCII) / PLY (binary/ASCII) / KITTI .bin / text round trips and bad files.
#include <superloc/io/point_cloud_io.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <fstream>
#include <iterator>

using namespace superloc;
using namespace superloc::io;
using superloc::testing::freshDir;

namespace {

PointCloud makeCloud(size_t n, bool normals, bool rgb) {
    PointCloud c;
    for (size_t i = 0; i < n; ++i) {
        c.points.emplace_back(0.001f * i - 3.5f, std::sin(0.1f * i) * 20, 1e3f + 0.5f * i);
        c.intensity.push_back(0.25f * (i % 9));
        if (normals) c.normals.push_back(Vec3f(1, 2, 3 + i % 5).normalized());
        if (rgb) c.rgb.push_back({uint8_t(i), uint8_t(255 - i % 256), uint8_t(7 * i)});
    }
    return c;
}

void expectSame(const PointCloud& a, const PointCloud& b, bool intensity, bool normals, bool rgb,
                float tol) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) EXPECT_LE((a.points[i] - b.points[i]).norm(), tol) << i;
    if (intensity) {
        ASSERT_EQ(b.intensity.size(), a.size());
        for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a.intensity[i], b.intensity[i], tol);
    }
    if (normals) {
        ASSERT_EQ(b.normals.size(), a.size());
        for (size_t i = 0; i < a.size(); ++i)
            EXPECT_LE((a.normals[i] - b.normals[i]).norm(), 1e-6f);
    }
    if (rgb) {
        ASSERT_EQ(b.rgb.size(), a.size());
        for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a.rgb[i], b.rgb[i]);
    }
}

void writeFile(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

/// Expects loadPointCloud to throw a one-line error naming the file.
void expectLoadError(const std::string& path, const std::string& fragment = "") {
    try {
        const auto c = loadPointCloud(path);
        ADD_FAILURE() << path << ": loaded " << c.size() << " points, expected an error";
    } catch (const std::runtime_error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(path), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        if (!fragment.empty()) {
            EXPECT_NE(m.find(fragment), std::string::npos) << m;
        }
    }
}

}  // namespace

TEST(PointCloudIo, RoundTripsEveryFormat) {
    const auto dir = freshDir("cloud_rt");
    const PointCloud full = makeCloud(1000, true, true);
    struct Case {
        const char* file;
        CloudFormat fmt;
        bool i, n, c;
        float tol;
    };
    const Case cases[] = {
        {"a.pcd", CloudFormat::PcdBinary, true, true, true, 0},
        {"b.pcd", CloudFormat::PcdAscii, true, true, true, 1e-3f},
        {"c.ply", CloudFormat::Ply, true, true, true, 0},
        {"d.ply", CloudFormat::PlyAscii, true, true, true, 1e-3f},
        {"e.bin", CloudFormat::KittiBin, true, false, false, 0},
        {"f.txt", CloudFormat::Text, true, false, false, 1e-3f},
    };
    for (const auto& k : cases) {
        SCOPED_TRACE(k.file);
        const std::string path = dir + "/" + k.file;
        savePointCloud(path, full, k.fmt);
        const PointCloud back = loadPointCloud(path);
        expectSame(full, back, k.i, k.n, k.c, k.tol);
    }
    // Points only (no attribute) stay attribute-free.
    PointCloud bare;
    bare.points = full.points;
    for (const char* f : {"g.pcd", "h.ply", "i.txt"}) {
        savePointCloud(dir + "/" + f, bare);
        const auto back = loadPointCloud(dir + "/" + f);
        EXPECT_EQ(back.size(), bare.size());
        EXPECT_TRUE(back.intensity.empty()) << f;
        EXPECT_TRUE(back.normals.empty()) << f;
    }
}

TEST(PointCloudIo, EmptyCloudRoundTrips) {
    const auto dir = freshDir("cloud_empty");
    for (const char* f : {"e.pcd", "e.ply", "e.bin", "e.txt"}) {
        savePointCloud(dir + "/" + f, PointCloud());
        EXPECT_EQ(loadPointCloud(dir + "/" + f).size(), 0u) << f;
    }
}

TEST(PointCloudIo, DropsAndCountsNonFinitePoints) {
    const auto dir = freshDir("cloud_nan");
    PointCloud c = makeCloud(50, true, false);
    c.points[3].x() = std::nanf("");
    c.points[10].z() = -INFINITY;
    for (const char* f : {"n.pcd", "n.ply", "n.bin"}) {
        savePointCloud(dir + "/" + f, c);
        size_t dropped = 0;
        const auto back = loadPointCloud(dir + "/" + f, CloudFormat::Auto, &dropped);
        EXPECT_EQ(dropped, 2u) << f;
        EXPECT_EQ(back.size(), 48u) << f;
        EXPECT_EQ(back.intensity.size(), 48u) << f;
        EXPECT_FLOAT_EQ(back.intensity[3], c.intensity[4]) << f;  // attributes stay aligned
    }
}

TEST(PointCloudIo, BadFilesGiveOneLineErrors) {
    const auto dir = freshDir("cloud_bad");
    expectLoadError(dir + "/missing.pcd", "not found");
    expectLoadError(dir + "/missing.ply", "not found");
    writeFile(dir + "/x.las", "junk");
    expectLoadError(dir + "/x.las", "unknown point-cloud extension");

    const PointCloud c = makeCloud(5000, true, false);
    for (const char* f : {"t.pcd", "t.ply", "t.bin"}) {
        savePointCloud(dir + "/" + f, c);
        const std::string bytes = readFile(dir + "/" + f);
        writeFile(dir + "/trunc_" + std::string(f), bytes.substr(0, bytes.size() / 2 + 3));
        expectLoadError(dir + "/trunc_" + std::string(f));
    }
    savePointCloud(dir + "/a.pcd", c, CloudFormat::PcdAscii);
    const std::string ascii = readFile(dir + "/a.pcd");
    writeFile(dir + "/trunc_a.pcd", ascii.substr(0, ascii.size() / 2));
    expectLoadError(dir + "/trunc_a.pcd");
    savePointCloud(dir + "/a.ply", c, CloudFormat::PlyAscii);
    const std::string aply = readFile(dir + "/a.ply");
    writeFile(dir + "/trunc_a.ply", aply.substr(0, aply.size() / 2));
    expectLoadError(dir + "/trunc_a.ply", "truncated");

    writeFile(dir + "/garbage.pcd", "VERSION banana\nFIELDS x y\n\x01\x02\x03");
    expectLoadError(dir + "/garbage.pcd");
    writeFile(dir + "/garbage.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n");
    expectLoadError(dir + "/garbage.ply", "end_header");
    writeFile(dir + "/noxyz.ply",
              "ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\nend_header\n1\n");
    expectLoadError(dir + "/noxyz.ply", "no x y z");
    writeFile(dir + "/notply.ply", "solid cube\n");
    expectLoadError(dir + "/notply.ply", "magic");
    // Counts claiming far more points than the file holds are refused before allocating.
    writeFile(dir + "/huge.ply",
              "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
              "property float x\nproperty float y\nproperty float z\nend_header\n0123456789ab");
    expectLoadError(dir + "/huge.ply", "truncated");
    writeFile(dir + "/huge_ascii.ply",
              "ply\nformat ascii 1.0\nelement vertex 4000000000\n"
              "property float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n");
    expectLoadError(dir + "/huge_ascii.ply", "truncated");
    writeFile(dir + "/huge.pcd",
              "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 4000000000\n"
              "HEIGHT 1\nPOINTS 4000000000\nDATA ascii\n1 2 3\n");
    expectLoadError(dir + "/huge.pcd", "truncated");
    writeFile(dir + "/bad.txt", "1 2 3\n4 five 6\n");
    expectLoadError(dir + "/bad.txt", ":2:");
    // ASCII PCD data (issue 36): PCL reads a word as 0 and pads a short line with zeros (a point
    // at the origin), and drops the lines past POINTS; each is an error naming file and line.
    const std::string head =
        "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 2\n"
        "HEIGHT 1\nPOINTS 2\nDATA ascii\n";
    writeFile(dir + "/word.pcd", head + "1 2 3 4\n1 two 3 4\n");
    expectLoadError(dir + "/word.pcd", "word.pcd:11: 'two' is not a number");
    writeFile(dir + "/short.pcd", head + "1.5 2.5 3.5\n1.5 2.5 3.5 4.5\n");
    expectLoadError(dir + "/short.pcd", "short.pcd:10: 3 values, the header's FIELDS/COUNT say 4");
    writeFile(dir + "/more.pcd", head + "1 2 3 4\n\n5 6 7 8\n9 10 11 12\n");
    expectLoadError(dir + "/more.pcd", "more.pcd:13: more data lines than the header's 2 points");
    writeFile(dir + "/nan.pcd", head + "nan nan nan 0\n1 2 3 4\n");  // PCL writes NaN as nan
    EXPECT_EQ(loadPointCloud(dir + "/nan.pcd").size(), 1u);
}

TEST(PointCloudIo, ReadsRealPcdScanAndKittiBin) {
    SUPERLOC_REQUIRE_DATA("campus-ouster/scans");
    SUPERLOC_REQUIRE_DATA("kitti00-mini/velodyne/000000.bin");
    const auto pcd =
        loadPointCloud(superloc::testing::sharedData("scan-pair-outdoor/251370668.pcd"));
    EXPECT_GT(pcd.size(), 60000u);
    const auto bin =
        loadPointCloud(superloc::testing::sharedData("kitti00-mini/velodyne/000000.bin"));
    EXPECT_GT(bin.size(), 100000u);
    ASSERT_EQ(bin.intensity.size(), bin.size());
    for (float i : bin.intensity) ASSERT_TRUE(i >= 0 && i <= 255);  // this copy is 0..255
}
