// IMU and odometry CSV files (--imu-csv, --odom-csv): parsing, errors naming file and line, and
// their samples interleaved by time into a KITTI import.
#include <superloc/core/se3.h>
#include <superloc/io/importers.h>
#include <superloc/io/rawlog.h>
#include <superloc_testing/testing.h>

#include <fstream>

namespace {

using namespace superloc;

std::string write(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
    return path;
}

using superloc::testing::errorOf;

}  // namespace

TEST(Csv, ImuWithHeaderCommasAndBlanks) {
    const auto dir = superloc::testing::freshDir("csv_imu");
    const auto imu = io::loadImuCsv(write(dir + "/imu.csv",
                                          "t,ax,ay,az,wx,wy,wz\n"
                                          "0.0, 0.1, 0.2, 9.8, 0.01, 0.02, 0.03\n"
                                          "# comment\n\n"
                                          "0.005 0.2 0.3 9.7 -0.01 -0.02 -0.03\n"));
    ASSERT_EQ(imu.size(), 2u);
    EXPECT_EQ(imu[1].t, 0.005);
    EXPECT_EQ(imu[0].acc, Vec3d(0.1, 0.2, 9.8));
    EXPECT_EQ(imu[1].gyro, Vec3d(-0.01, -0.02, -0.03));
}

TEST(Csv, OdometryWithAndWithoutCovariance) {
    const auto dir = superloc::testing::freshDir("csv_odom");
    std::string cov;
    for (int i = 1; i <= 21; ++i) cov += " " + std::to_string(i);
    const auto odom = io::loadOdomCsv(
        write(dir + "/odom.csv", "1.0 1 2 3 0 0 0 1\n1.1 1 2 3 0 0 0.7071068 0.7071068" + cov + "\n"));
    ASSERT_EQ(odom.size(), 2u);
    EXPECT_FALSE(odom[0].cov.has_value());
    EXPECT_TRUE(odom[1].pose.isApprox(makePoseRPY(1, 2, 3, 0, 0, M_PI / 2), 1e-6));
    ASSERT_TRUE(odom[1].cov.has_value());
    EXPECT_EQ((*odom[1].cov)(0, 0), 1);
    EXPECT_EQ((*odom[1].cov)(0, 5), 6);
    EXPECT_EQ((*odom[1].cov)(5, 0), 6);
    EXPECT_EQ((*odom[1].cov)(1, 1), 7);
    EXPECT_EQ((*odom[1].cov)(5, 5), 21);
}

TEST(Csv, ErrorsNameFileAndLine) {
    const auto dir = superloc::testing::freshDir("csv_bad");
    const std::vector<std::pair<std::string, std::string>> imu_cases = {
        {"0 1 2 3 4 5 6\n1 1 2 3 4 5\n", ":2: 6 values, expected 7"},
        {"0 1 2 3 4 5 6\n0 1 2 3 4 5 6\n", ":2: time does not increase"},
        {"t ax\n0 1 2 3 4 5 6\nabc 1 2 3 4 5 6\n", ":3: not a row of numbers"},
        {"0 1 2 nan 4 5 6\n", ":1: NaN or infinite"},
        {"# nothing\n", ": no data rows"},
    };
    for (const auto& [text, want] : imu_cases) {
        const auto path = write(dir + "/imu.csv", text);
        const auto e = errorOf([&] { io::loadImuCsv(path); });
        EXPECT_NE(e.find(path + want), std::string::npos) << e;
    }
    const auto path = write(dir + "/odom.csv", "0 1 2 3 0 0 0 1\n1 1 2 3 0 0 0 2\n");
    const auto e = errorOf([&] { io::loadOdomCsv(path); });
    EXPECT_NE(e.find(path + ":2: quaternion norm"), std::string::npos) << e;
    EXPECT_NE(errorOf([&] { io::loadImuCsv(dir + "/none.csv"); }).find(dir + "/none.csv: cannot open"),
              std::string::npos);
}

TEST(Csv, InterleavedIntoKittiImport) {
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("csv_kitti");
    io::ImportExtras ex;
    for (int k = 0; k < 320; ++k) {  // 200 Hz over the 16 scans (1.56 s)
        ImuSample s;
        s.t = 0.005 * k;
        s.acc = Vec3d(0, 0, 9.81);
        ex.imu.push_back(s);
    }
    for (int k = 0; k < 40; ++k) {
        PoseStamped p;
        p.t = 0.04 * k;
        p.pose.translation() = Vec3d(0.5 * p.t, 0, 0);
        p.cov = Mat6d::Identity() * 0.01;
        ex.odom_alt.push_back(p);
    }
    const auto r = io::importKitti(superloc::testing::sharedData("kitti00-mini"), "", "",
                                   dir + "/k.rawlog", {}, ex);
    EXPECT_EQ(r.imu, 320u);
    EXPECT_EQ(r.odom_alt, 40u);
    io::RawlogReader reader(dir + "/k.rawlog");
    io::RawlogItem it;
    double last = -1;
    while (reader.next(it)) {
        EXPECT_GE(it.time(), last);
        last = it.time();
    }
    EXPECT_EQ(reader.stats().lidar, 16u);
    EXPECT_EQ(reader.stats().imu, 320u);
    EXPECT_EQ(reader.stats().odom_alt, 40u);
}
