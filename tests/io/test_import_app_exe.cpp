// The superloc-import executable itself: exit codes, one-line errors, a real KITTI import.
#include <superloc/io/rawlog.h>
#include <superloc/io/tum.h>
#include <superloc_testing/bag_writers.h>
#include <superloc_testing/recorded_bag.h>
#include <superloc_testing/testing.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

const std::string kExe = superloc::testing::appPath("superloc-import");

struct ExeResult {
    int code;
    std::string out, err;
};

std::string slurp(const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

ExeResult runExe(const std::string& args, const std::string& dir) {
    const int rc = std::system(
        (kExe + " " + args + " > " + dir + "/stdout.txt 2> " + dir + "/stderr.txt").c_str());
    return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, slurp(dir + "/stdout.txt"),
            slurp(dir + "/stderr.txt")};
}

}  // namespace

TEST(SuperlocImportExe, HelpAndBadInput) {
    if (!std::filesystem::exists(kExe)) GTEST_SKIP() << "superloc-import not built: " << kExe;
    const auto dir = superloc::testing::freshDir("import_exe_bad");
    const auto help = runExe("--help", dir);
    EXPECT_EQ(help.code, 0);
    EXPECT_NE(help.out.find("Usage: superloc-import"), std::string::npos);
    std::ofstream(dir + "/bad.tum") << "0 1 2\n";
    for (const std::string& args :
         {std::string("--kitti /nonexistent --out x.rawlog"), std::string("--frobnicate"),
          std::string("--kitti a --pcd-dir b --out x.rawlog"), std::string("--kitti"),
          std::string("--pcd-dir ") + dir + " --poses " + dir + "/bad.tum --out x.rawlog"}) {
        const ExeResult r = runExe(args, dir);
        EXPECT_NE(r.code, 0) << args;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
        EXPECT_EQ(r.err.rfind("superloc-import: ", 0), 0u) << r.err;
    }
}

TEST(SuperlocImportExe, ImportsKittiMini) {
    if (!std::filesystem::exists(kExe)) GTEST_SKIP() << "superloc-import not built: " << kExe;
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    const auto dir = superloc::testing::freshDir("import_exe_kitti");
    const auto data = superloc::testing::sharedData("kitti00-mini");
    const ExeResult r = runExe(
        "--kitti " + data + " --poses " + data + "/gt_velodyne_tum.txt --out " + dir + "/k.rawlog",
        dir);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("16 scans, 1959619 points, 16 gt poses"), std::string::npos) << r.out;
    superloc::io::RawlogReader reader(dir + "/k.rawlog");
    superloc::io::RawlogItem it;
    while (reader.next(it)) {
    }
    EXPECT_EQ(reader.stats().lidar, 16u);
    EXPECT_EQ(reader.stats().gt, 16u);
}

#ifdef SUPERLOC_HAVE_ROS1
TEST(SuperlocImportExe, RosbagListImportAndErrors) {
    if (!std::filesystem::exists(kExe)) GTEST_SKIP() << "superloc-import not built: " << kExe;
    SUPERLOC_REQUIRE_DATA("rosbag-kitti00-mini/kitti00-mini.bag");
    const auto dir = superloc::testing::freshDir("import_exe_rosbag");
    const auto bag = superloc::testing::sharedData("rosbag-kitti00-mini/kitti00-mini.bag");
    const ExeResult list = runExe("--rosbag " + bag + " --list", dir);
    ASSERT_EQ(list.code, 0) << list.err;
    EXPECT_NE(list.out.find("/velodyne_points  sensor_msgs/PointCloud2  16 messages"),
              std::string::npos) << list.out;
    const ExeResult r = runExe("--rosbag " + bag + " --set rosbag.gt_topic=/ground_truth --out " +
                                   dir + "/b.rawlog --gt-tum " + dir + "/gt.tum",
                               dir);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("16 scans (/velodyne_points, 0 with per-point time), 1959619 points"),
              std::string::npos) << r.out;
    EXPECT_EQ(superloc::io::loadTum(dir + "/gt.tum").size(), 16u);
    for (const std::string args : {"--set rosbag.gt_topic=/nope", "--set rosbag.imu_topic=/tf_static",
                                   "--set rosbag.frobnicate=1", "--poses x.tum"}) {
        const ExeResult e = runExe("--rosbag " + bag + " " + args + " --out " + dir + "/x.rawlog", dir);
        EXPECT_NE(e.code, 0) << args;
        EXPECT_EQ(std::count(e.err.begin(), e.err.end(), '\n'), 1) << args << ": " << e.err;
    }
}
#endif

#ifdef SUPERLOC_HAVE_ROS1
// The ROS 1 bag of issue 29, tried as a new user would: 412 PointCloud2 scans with
// header.stamp = 0 and an empty frame_id, an IMU whose header clock is 3 days from the record
// time. Each run names what is wrong in one line, and the keys it names make the import work.
TEST(SuperlocImportExe, RosbagWithUnsetStampsOtherClocksAndNoFrame) {
    if (!std::filesystem::exists(kExe)) GTEST_SKIP() << "superloc-import not built: " << kExe;
    namespace bw = superloc::testing::bag;
    const auto dir = superloc::testing::freshDir("import_exe_robot_bag");
    const std::string bag = dir + "/robot.bag", out = " --out " + dir + "/r.rawlog";
    bw::Recording rec;
    rec.scans = 412;
    rec.lidar_stamps = false;
    rec.lidar_frame = "";
    rec.imu_clock_offset_ns = -259200LL * 1000000000LL;
    bw::writeRos1Recording(bag, rec);
    const auto expectOneLineError = [&](const std::string& args, const std::string& part) {
        const ExeResult e = runExe("--rosbag " + bag + " " + args + out, dir);
        EXPECT_EQ(e.code, 1) << args;
        EXPECT_EQ(std::count(e.err.begin(), e.err.end(), '\n'), 1) << args << ": " << e.err;
        EXPECT_EQ(e.err.rfind("superloc-import: " + bag + ": ", 0), 0u) << e.err;
        EXPECT_NE(e.err.find(part), std::string::npos) << e.err;
        EXPECT_FALSE(std::filesystem::exists(dir + "/r.rawlog")) << args;
    };
    // stamp_source = auto: the scans on the record time, the IMU on its own clock.
    expectOneLineError("", "topic '/points' (record time, 1700000000.060 to 1700000041.160 s) and "
                           "topic '/imu' (header.stamp, 1699740799.950 to 1699740841.250 s) do "
                           "not overlap and their clocks differ by 259200.002 s");
    // Both on the record time: next, the LiDAR's frame.
    expectOneLineError("--set rosbag.stamp_source=record",
                       "topic '/points': empty header.frame_id, so no static transform from "
                       "'imu_link' to the LiDAR can be looked up (set [rosbag] lidar_extrinsic)");
    const ExeResult ok = runExe("--rosbag " + bag +
                                    " --set rosbag.stamp_source=record"
                                    " --set 'rosbag.lidar_extrinsic=0.1 0 0.2 0 0 0 1'" + out,
                                dir);
    ASSERT_EQ(ok.code, 0) << ok.err;
    EXPECT_EQ(ok.err, "");
    EXPECT_NE(ok.out.find("412 scans (/points, 412 with per-point time 't'), 41200 points, 4131 imu"),
              std::string::npos) << ok.out;
    // The LiDAR alone under auto: every scan, and one notice saying why.
    const ExeResult lidar = runExe("--rosbag " + bag + " --set rosbag.imu_topic=none" + out, dir);
    ASSERT_EQ(lidar.code, 0) << lidar.err;
    EXPECT_NE(lidar.out.find("412 scans"), std::string::npos) << lidar.out;
    EXPECT_EQ(lidar.err, "superloc-import: notice: " + bag +
                             ": topic '/points': header.stamp is 0 on 412 of 412 messages: stamped "
                             "with the bag's record time instead ([rosbag] stamp_source = auto; "
                             "header keeps header.stamp)\n");
    // The keys are in --dump-config, and checked.
    const ExeResult dump = runExe("--dump-config", dir);
    EXPECT_NE(dump.out.find("stamp_source                                       =  auto"),
              std::string::npos) << dump.out;
    EXPECT_NE(dump.out.find("max_clock_offset                                   =  1.0"),
              std::string::npos) << dump.out;
    const ExeResult bad = runExe("--rosbag " + bag + " --set rosbag.stamp_source=frame" + out, dir);
    EXPECT_EQ(bad.code, 1);
    EXPECT_EQ(bad.err, "superloc-import: [rosbag] stamp_source must be auto, header or record, "
                       "not 'frame'\n");
    // stamp_source = header: what the import did before, 1 of 412 scans and a warning.
    const ExeResult header =
        runExe("--rosbag " + bag + " --set rosbag.imu_topic=none --set rosbag.stamp_source=header" +
                   out, dir);
    ASSERT_EQ(header.code, 0) << header.err;
    EXPECT_NE(header.out.find(": 1 scans"), std::string::npos) << header.out;
    EXPECT_EQ(header.err, "superloc-import: warning: " + bag +
                              ": topic '/points': 411 messages skipped (header.stamp did not "
                              "increase)\n");
}
#endif

// ROS 2 bags through the executable: --list and an import of a .db3 and an MCAP written by the
// test writers (two real KITTI scans cut to 1000 points), and a one-line error for an MCAP
// chunk with an unknown compression.
TEST(SuperlocImportExe, Ros2BagListImportAndErrors) {
    if (!std::filesystem::exists(kExe)) GTEST_SKIP() << "superloc-import not built: " << kExe;
    SUPERLOC_REQUIRE_DATA("kitti00-mini");
    namespace bw = superloc::testing::bag;
    const auto dir = superloc::testing::freshDir("import_exe_ros2bag");
    std::vector<bw::Message> msgs;
    for (int k = 0; k < 2; ++k) {
        char name[64];
        std::snprintf(name, sizeof(name), "kitti00-mini/velodyne/%06d.bin", k);
        std::ifstream in(superloc::testing::sharedData(name), std::ios::binary);
        bw::Cloud c;
        c.stamp = {100 + k, 0};
        c.frame = "velodyne";
        c.data.resize(1000 * 16);
        in.read(reinterpret_cast<char*>(c.data.data()), std::streamsize(c.data.size()));
        c.width = 1000;
        c.point_step = 16;
        c.row_step = 16000;
        c.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"intensity", 12, 7, 1}};
        msgs.push_back({"/points", "sensor_msgs/msg/PointCloud2", c.stamp.ns(), bw::cdr(c)});
    }
    bw::writeDb3(dir + "/k.db3", msgs);
    bw::writeMcap(dir + "/k.mcap", msgs);
    for (const std::string f : {"k.db3", "k.mcap"}) {
        const ExeResult list = runExe("--rosbag " + dir + "/" + f + " --list", dir);
        ASSERT_EQ(list.code, 0) << list.err;
        EXPECT_EQ(list.out, "/points  sensor_msgs/msg/PointCloud2  2 messages\n");
        const ExeResult r = runExe("--rosbag " + dir + "/" + f + " --out " + dir + "/x.rawlog", dir);
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.out.find("2 scans (/points, 0 with per-point time), 2000 points"),
                  std::string::npos) << r.out;
    }
    bw::McapOptions o;
    o.compression = "brotli";
    bw::writeMcap(dir + "/b.mcap", msgs, o);
    const ExeResult e = runExe("--rosbag " + dir + "/b.mcap --out " + dir + "/x.rawlog", dir);
    EXPECT_NE(e.code, 0);
    EXPECT_EQ(std::count(e.err.begin(), e.err.end(), '\n'), 1) << e.err;
    EXPECT_NE(e.err.find(dir + "/b.mcap: MCAP: chunk (record 0x06 at byte 42, compression "
                               "'brotli'): unknown compression"),
              std::string::npos) << e.err;
}
