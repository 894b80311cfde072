// MapBuilder / superloc-map: scans of a synthetic box room written as a rawlog, placed at
// their poses (TUM or the rawlog's gt), must give a map whose points lie on the room's walls.
#include <superloc/core/config.h>
#include <superloc/core/se3.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/rawlog.h>
#include <superloc/io/tum.h>
#include <superloc/app/command_line.h>
#include <superloc/app/map_app.h>
#include <superloc/map/map_builder.h>
#include <superloc/map/prior_map.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <random>

using namespace superloc;

namespace {

// Room [0,10] x [0,6] x [0,3] m; distance of a point to its nearest face.
double distanceToRoom(const Vec3f& p) {
    const double dx = std::min(std::abs(p.x()), std::abs(p.x() - 10.f));
    const double dy = std::min(std::abs(p.y()), std::abs(p.y() - 6.f));
    const double dz = std::min(std::abs(p.z()), std::abs(p.z() - 3.f));
    return std::min({dx, dy, dz});
}

/// A 360 x 32-beam sweep from T_map_lidar, ray-cast analytically against the room.
Scan sweep(const SE3d& T_map_lidar, double t) {
    Scan s;
    s.t = t;
    const Mat3d R = T_map_lidar.linear();
    const Vec3d o = T_map_lidar.translation();
    for (int e = 0; e < 32; ++e)
        for (int a = 0; a < 360; ++a) {
            const double el = (-30.0 + 60.0 * e / 31) * M_PI / 180, az = a * M_PI / 180;
            const Vec3d d_l(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
            const Vec3d d = R * d_l;
            double best = 1e9;
            const double lo[3] = {0, 0, 0}, hi[3] = {10, 6, 3};
            for (int k = 0; k < 3; ++k) {
                if (std::abs(d[k]) < 1e-9) continue;
                const double r = ((d[k] > 0 ? hi[k] : lo[k]) - o[k]) / d[k];
                if (r > 0) best = std::min(best, r);
            }
            s.points.push_back((best * d_l).cast<float>());
            s.intensity.push_back(static_cast<float>(e));
        }
    return s;
}

struct Fixture {
    std::string dir, rawlog, tum;
    Trajectory poses;
};

Fixture writeRoomRawlog(const std::string& name, bool with_gt) {
    Fixture f;
    f.dir = superloc::testing::freshDir(name);
    f.rawlog = f.dir + "/room.rawlog";
    f.tum = f.dir + "/poses.tum";
    io::RawlogWriter w(f.rawlog);
    for (int i = 0; i < 6; ++i) {
        PoseStamped p;
        p.t = 100.0 + 0.5 * i;
        p.pose = makePoseRPY(2.0 + 1.0 * i, 3.0 + 0.2 * i, 1.5, 0.05 * i, -0.03 * i, 0.3 * i);
        f.poses.push_back(p);
        w.writeScan(sweep(p.pose, p.t));
        if (with_gt) w.writePose(p, "gt");
    }
    w.close();
    io::saveTum(f.tum, f.poses);
    return f;
}

}  // namespace

TEST(MapBuilder, RoomScansAtTheirPosesLieOnTheWalls) {
    const Fixture f = writeRoomRawlog("map_builder_room", true);
    for (const bool from_gt : {false, true}) {
        map::MapBuildOptions o;
        o.rawlog = f.rawlog;
        o.poses_tum = from_gt ? "" : f.tum;
        o.voxel = 0.1;
        map::MapBuilder b(o);
        const PointCloud m = b.build();
        EXPECT_EQ(b.result().scans_used, 6u);
        EXPECT_EQ(b.result().scans_without_pose, 0u);
        EXPECT_EQ(b.result().points_in, 6u * 360u * 32u);
        EXPECT_EQ(m.size(), b.result().map_points);
        EXPECT_GT(m.size(), 3000u);
        EXPECT_LT(m.size(), 6u * 360u * 32u);
        ASSERT_EQ(m.intensity.size(), m.size());
        size_t off = 0;
        for (const auto& p : m.points) off += distanceToRoom(p) > 0.01 ? 1 : 0;
        // Centroids of a voxel straddling an edge of the room may sit off both faces.
        EXPECT_LT(off, m.size() / 50) << (from_gt ? "gt" : "tum");
    }
}

TEST(MapBuilder, WrongPosesBlurTheWalls) {
    // The same scans with every pose shifted by a different amount must not give sharp walls:
    // the test above is able to fail.
    Fixture f = writeRoomRawlog("map_builder_blur", false);
    for (size_t i = 0; i < f.poses.size(); ++i)
        f.poses[i].pose.translation() += Vec3d(0.1 * i, -0.07 * i, 0.05 * i);
    io::saveTum(f.tum, f.poses);
    map::MapBuildOptions o;
    o.rawlog = f.rawlog;
    o.poses_tum = f.tum;
    const PointCloud m = map::MapBuilder(o).build();
    size_t off = 0;
    for (const auto& p : m.points) off += distanceToRoom(p) > 0.01 ? 1 : 0;
    EXPECT_GT(off, m.size() / 5);
}

TEST(MapBuilder, NoVoxelKeepsEveryPointAndRangeFilterDrops) {
    const Fixture f = writeRoomRawlog("map_builder_novoxel", false);
    map::MapBuildOptions o;
    o.rawlog = f.rawlog;
    o.poses_tum = f.tum;
    o.voxel = 0;
    o.min_range = 0;
    map::MapBuilder all(o);
    EXPECT_EQ(all.build().size(), 6u * 360u * 32u);
    o.max_range = 3.0;
    map::MapBuilder near(o);
    const size_t kept = near.build().size();
    EXPECT_GT(kept, 0u);
    EXPECT_LT(kept, 6u * 360u * 32u);
}

TEST(MapBuilder, ScansOutsideThePosesAreCountedAndMissingGtIsAnError) {
    const Fixture f = writeRoomRawlog("map_builder_partial", false);
    Trajectory half(f.poses.begin(), f.poses.begin() + 3);
    io::saveTum(f.tum, half);
    map::MapBuildOptions o;
    o.rawlog = f.rawlog;
    o.poses_tum = f.tum;
    map::MapBuilder b(o);
    b.build();
    EXPECT_EQ(b.result().scans_used, 3u);
    EXPECT_EQ(b.result().scans_without_pose, 3u);

    o.poses_tum.clear();  // the rawlog has no gt
    try {
        map::MapBuilder(o).build();
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("gt"), std::string::npos) << e.what();
    }
}

TEST(MapApp, CommandLineErrorsAreOneLine) {
    const auto parse = [](std::vector<const char*> v) {
        v.insert(v.begin(), "superloc-map");
        return app::parseMapAppArgs(app::argList(static_cast<int>(v.size()), v.data()));
    };
    EXPECT_TRUE(parse({"--help"}).help);
    for (const auto& bad : std::vector<std::vector<const char*>>{
             {"--rawlog"},
             {"--rawlog", "/nonexistent.rawlog", "--out", "m.pcd"},
             {"--out", "m.pcd"},
             {"--rawlog", "x.rawlog", "--out", "m.unknown"},
             {"--voxel", "abc"},
             {"--frobnicate"}}) {
        try {
            parse(bad);
            ADD_FAILURE() << "no error for " << bad[0];
        } catch (const std::runtime_error& e) {
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        }
    }
}

TEST(MapApp, WritesTheMapAndItsStats) {
    const Fixture f = writeRoomRawlog("map_app_room", true);
    const std::string out = f.dir + "/map.pcd";
    std::vector<const char*> argv = {"superloc-map", "--rawlog", f.rawlog.c_str(), "--out",
                                     out.c_str(), "--voxel", "0.05", "--stats"};
    app::MapApp map_app(app::parseMapAppArgs(app::argList(static_cast<int>(argv.size()), argv.data())));
    map_app.run();
    const PointCloud m = io::loadPointCloud(out);
    EXPECT_EQ(m.size(), map_app.result().map_points);
    ASSERT_TRUE(map_app.stats().has_value());
    EXPECT_EQ(map_app.stats()->points, m.size());
    EXPECT_LT(map_app.stats()->median_planar_fit_residual, 0.005);  // exact walls: ~0 m
    EXPECT_GT(map_app.stats()->planar_fraction, 0.5);
}

TEST(MapApp, UnknownIniKeyIsAnError) {
    const Fixture f = writeRoomRawlog("map_app_ini", true);
    const std::string out = f.dir + "/map.pcd";
    std::vector<const char*> argv = {"superloc-map", "--rawlog", f.rawlog.c_str(), "--out",
                                     out.c_str(), "--set", "rawlog.gt_lable=x"};
    EXPECT_THROW(app::parseMapAppArgs(app::argList(static_cast<int>(argv.size()), argv.data())), superloc::ConfigError);
}

TEST(MapBuilder, StoredNormalsFaceTheRoomInterior) {
    const Fixture f = writeRoomRawlog("map_builder_normals", true);
    map::MapBuildOptions o;
    o.rawlog = f.rawlog;
    map::MapBuilder b(o);
    const PointCloud m = b.build();
    ASSERT_EQ(m.normals.size(), m.size());
    size_t checked = 0, inward = 0;
    for (size_t i = 0; i < m.size(); ++i) {
        const Vec3f& p = m.points[i];
        // Points on the floor (away from the walls): the normal must be +z, toward the sensors.
        if (p.z() < 0.01f && p.x() > 1 && p.x() < 9 && p.y() > 1 && p.y() < 5) {
            ++checked;
            inward += m.normals[i].z() > 0.99f ? 1 : 0;
        }
    }
    ASSERT_GT(checked, 500u);
    EXPECT_EQ(inward, checked);

    // Saved and loaded, the PriorMap orients its own normals the same way.
    const std::string path = f.dir + "/map.pcd";
    io::savePointCloud(path, m);
    const map::PriorMap pm = map::PriorMap::load(path, map::MapParams{});
    size_t oriented = 0, agree = 0;
    const Vec3f centre(5, 3, 1.5);
    for (size_t i = 0; i < pm.size(); ++i) {
        const auto& g = pm.geometry(i);
        if (!g.oriented) continue;
        ++oriented;
        agree += g.normal.dot(centre - pm.point(i)) > 0 ? 1 : 0;
    }
    EXPECT_GT(oriented, pm.size() * 99 / 100);
    EXPECT_GT(agree, oriented * 98 / 100);

    o.normals = false;
    EXPECT_TRUE(map::MapBuilder(o).build().normals.empty());
}
