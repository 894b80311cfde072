// Rawlog write -> read round trip of every type, ordering, labels, and MRPT's Velodyne files.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/COutputLogger.h>
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/io/rawlog.h>
#include <superloc_testing/testing.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

using namespace superloc;
using namespace superloc::io;
using superloc::testing::freshDir;

namespace {

Scan makeScan(double t, int n) {
    Scan s;
    s.t = t;
    for (int i = 0; i < n; ++i) {
        const double a = 2 * M_PI * i / n;
        s.points.emplace_back(5 * std::cos(a), 5 * std::sin(a), 0.1f * (i % 7));
        s.intensity.push_back(0.01f * i);
    }
    s.T_imu_lidar = makePoseRPY(0.1, -0.2, 0.3, 0.01, 0.02, 0.03);
    return s;
}

std::vector<RawlogItem> readAll(const std::string& path, RawlogStats* stats = nullptr,
                                const RawlogParams& p = {}) {
    RawlogReader r(path, p);
    std::vector<RawlogItem> items;
    RawlogItem it;
    while (r.next(it)) items.push_back(it);
    if (stats) *stats = r.stats();
    return items;
}

}  // namespace

TEST(Rawlog, RoundTripEveryType) {
    const auto path = freshDir("rawlog_rt") + "/a.rawlog";
    const Scan scan = makeScan(10.0, 360);
    ImuSample imu;
    imu.t = 10.01;
    imu.acc = Vec3d(0.1, -0.2, 9.81);
    imu.gyro = Vec3d(0.01, 0.02, -0.03);
    PoseStamped odom;
    odom.t = 10.02;
    odom.pose = makePoseRPY(1, 2, 3, 0.1, 0.2, 0.3);
    Mat6d cov = Mat6d::Identity() * 0.01;
    cov(0, 5) = cov(5, 0) = 0.001;  // x-yaw correlation survives the order conversion
    odom.cov = cov;
    PoseStamped gt;
    gt.t = 10.03;
    gt.pose = makePoseRPY(-1, 0.5, 0, 0, 0, 1.0);
    {
        RawlogWriter w(path);
        w.writeScan(scan);
        w.writeImu(imu);
        w.writePose(odom, "odom_alt");
        w.writePose(gt, "gt");
    }
    RawlogStats st;
    const auto items = readAll(path, &st);
    ASSERT_EQ(items.size(), 4u);
    EXPECT_EQ(st.lidar, 1u);
    EXPECT_EQ(st.imu, 1u);
    EXPECT_EQ(st.odom_alt, 1u);
    EXPECT_EQ(st.gt, 1u);

    ASSERT_EQ(items[0].kind, RawlogItem::Kind::Lidar);
    const Scan& s = items[0].scan();
    EXPECT_NEAR(s.t, scan.t, 1e-6);
    EXPECT_EQ(s.label, "lidar");
    ASSERT_EQ(s.size(), scan.size());
    ASSERT_EQ(s.intensity.size(), scan.size());
    for (size_t i = 0; i < s.size(); ++i) {
        EXPECT_LT((s.points[i] - scan.points[i]).norm(), 1e-6f);
        EXPECT_FLOAT_EQ(s.intensity[i], scan.intensity[i]);
    }
    EXPECT_LT(translationDistance(s.T_imu_lidar, scan.T_imu_lidar), 1e-9);
    EXPECT_LT(rotationAngle(s.T_imu_lidar, scan.T_imu_lidar), 1e-9);
    // Per-point time from the azimuth: sweep of 0.1 s ending at t, starting at 180 deg, CCW.
    ASSERT_EQ(s.rel_time.size(), s.size());
    for (size_t i = 0; i < s.size(); ++i) {
        EXPECT_LE(s.rel_time[i], 0.0f);
        EXPECT_GE(s.rel_time[i], -0.1f);
    }
    EXPECT_NEAR(s.rel_time[180], -0.1, 1e-4);   // azimuth 180 deg: first firing
    EXPECT_NEAR(s.rel_time[0], -0.05, 1e-4);    // azimuth 0: half a sweep later
    EXPECT_NEAR(s.rel_time[90], -0.025, 1e-4);  // azimuth 90 deg: CCW 180->270->0->90

    ASSERT_EQ(items[1].kind, RawlogItem::Kind::Imu);
    EXPECT_NEAR(items[1].imu().t, imu.t, 1e-6);
    EXPECT_LT((items[1].imu().acc - imu.acc).norm(), 1e-12);
    EXPECT_LT((items[1].imu().gyro - imu.gyro).norm(), 1e-12);

    ASSERT_EQ(items[2].kind, RawlogItem::Kind::OdomAlt);
    EXPECT_LT(translationDistance(items[2].pose().pose, odom.pose), 1e-9);
    EXPECT_LT(rotationAngle(items[2].pose().pose, odom.pose), 1e-9);
    ASSERT_TRUE(items[2].pose().cov.has_value());
    EXPECT_LT((*items[2].pose().cov - cov).norm(), 1e-12);

    ASSERT_EQ(items[3].kind, RawlogItem::Kind::GroundTruth);
    EXPECT_LT(translationDistance(items[3].pose().pose, gt.pose), 1e-9);
}

TEST(Rawlog, ReordersWithinWindowAndRejectsBeyond) {
    const auto dir = freshDir("rawlog_order");
    ImuSample a;
    {
        RawlogWriter w(dir + "/ok.rawlog");
        for (double t : {1.0, 1.2, 1.1, 1.3, 1.25}) {
            a.t = t;
            w.writeImu(a);
        }
    }
    const auto items = readAll(dir + "/ok.rawlog");
    ASSERT_EQ(items.size(), 5u);
    for (size_t i = 1; i < items.size(); ++i) EXPECT_LE(items[i - 1].time(), items[i].time());

    {
        RawlogWriter w(dir + "/back.rawlog");
        for (double t : {1.0, 2.0, 3.0, 1.5}) {
            a.t = t;
            w.writeImu(a);
        }
    }
    try {
        readAll(dir + "/back.rawlog");
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("back.rawlog: entry 4: timestamp goes backwards"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos);
    }
}

TEST(Rawlog, MemoryIsBoundedByTheReorderWindow) {
    // 60 s of 200 Hz IMU with 10 Hz scans: the reader never holds more than a window's worth.
    const auto path = freshDir("rawlog_stream") + "/long.rawlog";
    {
        RawlogWriter w(path);
        ImuSample s;
        for (int i = 0; i < 12000; ++i) {
            s.t = 100.0 + i * 0.005;
            w.writeImu(s);
            if (i % 20 == 0) w.writeScan(makeScan(s.t, 50));
        }
    }
    RawlogParams p;
    p.reorder_window = 0.25;
    RawlogStats st;
    const auto items = readAll(path, &st, p);
    EXPECT_EQ(items.size(), 12600u);
    EXPECT_GT(st.max_pending, 40u);
    EXPECT_LE(st.max_pending, 0.25 * 210 + 5);
}

TEST(Rawlog, CountsUnknownTypesOtherLabelsAndEmptyScans) {
    const auto path = freshDir("rawlog_unknown") + "/u.rawlog";
    {
        RawlogWriter w(path);
        mrpt::obs::CObservation2DRangeScan laser2d;
        laser2d.timestamp = mrpt::Clock::fromDouble(1.0);
        w.write(laser2d);
        PoseStamped p;
        p.t = 1.1;
        w.writePose(p, "wheel_odom");
        Scan empty;
        empty.t = 1.2;
        w.writeScan(empty);
        Scan nan = makeScan(1.3, 10);
        nan.points[3].x() = std::nanf("");
        nan.points[4].z() = INFINITY;
        w.writeScan(nan);
        w.writeScan(makeScan(1.4, 10), "other_lidar");
    }
    RawlogParams params;
    params.lidar_label = "lidar";
    RawlogReader reader(path, params);
    reader.logger().setMinLoggingLevel(mrpt::system::LVL_ERROR);  // the warnings are counted
    std::vector<RawlogItem> items;
    for (RawlogItem it; reader.next(it);) items.push_back(it);
    const RawlogStats st = reader.stats();
    ASSERT_EQ(items.size(), 1u);
    EXPECT_EQ(items[0].scan().size(), 8u);
    EXPECT_EQ(st.unknown_observations, 1u);
    EXPECT_EQ(st.other_pose_labels, 1u);
    EXPECT_EQ(st.empty_scans, 1u);
    EXPECT_EQ(st.invalid_points, 2u);
    EXPECT_EQ(st.skipped_labels, 1u);
    EXPECT_EQ(st.lidar, 1u);
}

TEST(Rawlog, MissingTruncatedAndCorruptFiles) {
    const auto dir = freshDir("rawlog_bad");
    EXPECT_THROW(RawlogReader(dir + "/nope.rawlog"), std::runtime_error);
    {
        RawlogWriter w(dir + "/full.rawlog");
        for (int i = 0; i < 20; ++i) w.writeScan(makeScan(i, 2000));
    }
    // Truncate the gz stream in the middle of the data.
    std::string bytes;
    {
        std::ifstream in(dir + "/full.rawlog", std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    {
        std::ofstream out(dir + "/trunc.rawlog", std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
    }
    {
        std::string junk = bytes;  // corrupt: garbage in the middle (not a valid gz stream)
        for (size_t i = junk.size() / 3; i < junk.size() / 3 + 200; ++i) junk[i] = char(i * 37);
        std::ofstream out(dir + "/corrupt.rawlog", std::ios::binary);
        out.write(junk.data(), static_cast<std::streamsize>(junk.size()));
    }
    {
        std::ofstream out(dir + "/text.rawlog");
        out << "this is not a rawlog at all\n";
    }
    for (const char* f : {"trunc.rawlog", "corrupt.rawlog", "text.rawlog"}) {
        try {
            const auto items = readAll(dir + "/" + f);
            ADD_FAILURE() << f << ": no error, " << items.size() << " items";
        } catch (const std::runtime_error& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find(f), std::string::npos) << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        }
    }
}

// Issue 36: a read error comes after every item read before it. The reader holds the newest
// reorder_window (0.5 s) back; those items used to be lost with the error.
TEST(Rawlog, AReadErrorComesAfterEveryItemReadBeforeIt) {
    const auto dir = freshDir("rawlog_error_after_items");
    {
        RawlogWriter w(dir + "/full.rawlog");
        for (int i = 0; i < 20; ++i) w.writeScan(makeScan(0.1 * i, 2000));
    }
    std::string bytes;
    {
        std::ifstream in(dir + "/full.rawlog", std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    std::ofstream(dir + "/cut.rawlog", std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
    const auto scansBeforeError = [&](double window) {
        RawlogParams p;
        p.reorder_window = window;
        RawlogReader r(dir + "/cut.rawlog", p);
        std::vector<double> t;
        RawlogItem it;
        try {
            while (r.next(it)) t.push_back(it.time());
            ADD_FAILURE() << "no error";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find("cut.rawlog: entry"), std::string::npos) << e.what();
        }
        EXPECT_FALSE(r.next(it));  // then the end
        return t;
    };
    const auto direct = scansBeforeError(0.0), windowed = scansBeforeError(0.5);
    EXPECT_GE(direct.size(), 5u);
    EXPECT_LT(direct.size(), 20u);
    EXPECT_EQ(windowed, direct);
}

TEST(Rawlog, RealVelodyneScansHavePerPointTime) {
    SUPERLOC_REQUIRE_DATA("mrpt-velodyne");
    for (const char* f :
         {"mrpt-velodyne/test_velodyne_VLP16.rawlog", "mrpt-velodyne/rot_scan_velodyne.rawlog"}) {
        RawlogStats st;
        const auto items = readAll(superloc::testing::sharedData(f), &st);
        SCOPED_TRACE(f);
        ASSERT_EQ(items.size(), 1u);
        const Scan& s = items[0].scan();
        EXPECT_GT(s.size(), 1000u);
        ASSERT_EQ(s.rel_time.size(), s.size());
        const auto [lo, hi] = std::minmax_element(s.rel_time.begin(), s.rel_time.end());
        EXPECT_GE(*lo, -0.2f);
        EXPECT_LE(*hi, 0.2f);
        EXPECT_GT(*hi - *lo, 0.01f);  // a sweep spans tens of ms
        for (const auto& p : s.points) {
            EXPECT_TRUE(p.allFinite());
            EXPECT_LT(p.norm(), 150.0f);
        }
    }
}

TEST(RawlogParams, LoadSaveValidate) {
    RawlogParams p;
    mrpt::config::CConfigFileMemory c;
    p.saveToConfigFile(c, "rawlog");
    RawlogParams q = superloc::loadParams<RawlogParams>(c, "rawlog", "mem.ini");
    EXPECT_EQ(q.gt_label, "gt");
    mrpt::config::CConfigFileMemory bad("[rawlog]\nscan_periode = 0.1\n");
    EXPECT_THROW(superloc::loadParams<RawlogParams>(bad, "rawlog", "x.ini"), superloc::ConfigError);
    mrpt::config::CConfigFileMemory wrong("[rawlog]\nscan_period = fast\n");
    EXPECT_THROW(superloc::loadParams<RawlogParams>(wrong, "rawlog", "x.ini"),
                 superloc::ConfigError);
    mrpt::config::CConfigFileMemory sense("[rawlog]\nrotation_sense = 2\n");
    EXPECT_THROW(superloc::loadParams<RawlogParams>(sense, "rawlog", "x.ini"),
                 superloc::ConfigError);
}

TEST(Rawlog, RotatingScanMatchesTheSameVelodyneScan) {
    // Both MRPT sample files hold the same VLP-16 sweep: raw packets, and fromVelodyne()'s
    // range image. Our range-image projection must reproduce MRPT's calibrated points.
    SUPERLOC_REQUIRE_DATA("mrpt-velodyne");
    const auto velo =
        readAll(superloc::testing::sharedData("mrpt-velodyne/test_velodyne_VLP16.rawlog"));
    const auto rot =
        readAll(superloc::testing::sharedData("mrpt-velodyne/rot_scan_velodyne.rawlog"));
    ASSERT_EQ(velo.size(), 1u);
    ASSERT_EQ(rot.size(), 1u);
    const auto& a = velo[0].scan().points;
    const auto& b = rot[0].scan().points;
    EXPECT_EQ(a.size(), b.size());
    std::vector<float> d;
    for (size_t i = 0; i < b.size(); i += 10) {
        float best = 1e9f;
        for (const auto& p : a) best = std::min(best, (p - b[i]).squaredNorm());
        d.push_back(std::sqrt(best));
    }
    std::sort(d.begin(), d.end());
    EXPECT_LT(d[d.size() / 2], 0.05f);
    EXPECT_LT(d[d.size() * 9 / 10], 0.15f);
}

TEST(Rawlog, ToleratesSensoryFrameFormatAndPlainPointMaps) {
    // The older action/sensory-frame layout, with a CSimplePointsMap cloud (no intensity).
    const auto path = freshDir("rawlog_sf") + "/sf.rawlog";
    {
        mrpt::io::CFileGZOutputStream f(path);
        auto arch = mrpt::serialization::archiveFrom(f);
        for (int k = 0; k < 3; ++k) {
            mrpt::obs::CActionCollection acts;
            mrpt::obs::CSensoryFrame sf;
            auto pc = mrpt::obs::CObservationPointCloud::Create();
            pc->timestamp = mrpt::Clock::fromDouble(5.0 + k);
            pc->sensorLabel = "lidar";
            auto m = mrpt::maps::CSimplePointsMap::Create();
            for (int i = 0; i < 100; ++i) m->insertPoint(float(i), 1.0f, 2.0f);
            pc->pointcloud = m;
            sf.insert(pc);
            auto imu = mrpt::obs::CObservationIMU::Create();
            imu->timestamp = mrpt::Clock::fromDouble(5.5 + k);
            for (auto idx : {mrpt::obs::IMU_X_ACC, mrpt::obs::IMU_Y_ACC, mrpt::obs::IMU_Z_ACC,
                             mrpt::obs::IMU_WX, mrpt::obs::IMU_WY, mrpt::obs::IMU_WZ})
                imu->set(idx, 0.5);
            sf.insert(imu);
            arch << acts << sf;
        }
    }
    RawlogStats st;
    const auto items = readAll(path, &st);
    ASSERT_EQ(items.size(), 6u);
    EXPECT_EQ(st.lidar, 3u);
    EXPECT_EQ(st.imu, 3u);
    EXPECT_EQ(items[0].scan().size(), 100u);
    EXPECT_TRUE(items[0].scan().intensity.empty());
    EXPECT_NEAR(items[5].time(), 7.5, 1e-6);
}

TEST(RawlogScans, SelectionSyntax) {
    io::RawlogParams p;
    const auto sel = [&](const std::string& s) {
        p.scans = s;
        return p.scanSelection();
    };
    EXPECT_TRUE(sel("all").contains(7));
    EXPECT_TRUE(sel("even").contains(4) && !sel("even").contains(5));
    EXPECT_TRUE(sel("odd").contains(5) && !sel("odd").contains(0));
    const auto r = sel("10:20:5");
    EXPECT_TRUE(r.contains(10) && r.contains(15) && !r.contains(20) && !r.contains(11) && !r.contains(5));
    EXPECT_TRUE(sel("3:").contains(1000) && !sel("3:").contains(2));
    EXPECT_TRUE(sel("0::5").contains(25) && !sel("0::5").contains(26));
    for (const char* bad : {"", "some", "5", ":3", "5:2", "1:2:0", "1:2:3:4", "-1:4", "a:b"}) {
        p.scans = bad;
        EXPECT_THROW(p.validate(), ConfigError) << bad;
        try {
            p.validate();
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("[rawlog] scans"), std::string::npos) << e.what();
        }
    }
}
