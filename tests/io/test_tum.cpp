// TUM trajectories: round trip at full precision, streaming writer, malformed lines.
#include <superloc/core/se3.h>
#include <superloc/io/tum.h>
#include <superloc_testing/testing.h>

using namespace superloc;
using namespace superloc::io;

namespace {
void writeText(const std::string& path, const std::string& s) { std::ofstream(path) << s; }

void expectTumError(const std::string& path, const std::string& fragment) {
    try {
        loadTum(path);
        ADD_FAILURE() << path << ": no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}
}  // namespace

TEST(Tum, RoundTripAndWriter) {
    const auto dir = superloc::testing::freshDir("tum");
    Trajectory traj;
    for (int i = 0; i < 20; ++i) {
        PoseStamped p;
        p.t = 1.6e9 + 0.1 * i + 1e-7;
        p.pose = makePoseRPY(0.1 * i, -3.0 + i, 1e-3 * i, 0.01 * i, -0.02 * i, 0.3 * i);
        traj.push_back(p);
    }
    saveTum(dir + "/a.tum", traj);
    {
        TumWriter w(dir + "/b.tum", "two lines\nof header");
        for (const auto& p : traj) w.write(p);
    }
    for (const char* f : {"a.tum", "b.tum"}) {
        const auto back = loadTum(dir + "/" + f);
        ASSERT_EQ(back.size(), traj.size());
        for (size_t i = 0; i < traj.size(); ++i) {
            EXPECT_NEAR(back[i].t, traj[i].t, 1e-8);
            EXPECT_LT(translationDistance(back[i].pose, traj[i].pose), 1e-9);
            EXPECT_LT(rotationAngle(back[i].pose, traj[i].pose), 1e-9);
        }
    }
}

TEST(Tum, MalformedFilesNameFileAndLine) {
    const auto dir = superloc::testing::freshDir("tum_bad");
    expectTumError(dir + "/none.tum", "none.tum: cannot open");
    writeText(dir + "/short.tum", "# c\n0 0 0 0 0 0 0 1\n1 2 3\n");
    expectTumError(dir + "/short.tum", "short.tum:3:");
    writeText(dir + "/back.tum", "1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n");
    expectTumError(dir + "/back.tum", "back.tum:2: timestamp goes backwards");
    writeText(dir + "/nan.tum", "1 nan 0 0 0 0 0 1\n");
    expectTumError(dir + "/nan.tum", "nan.tum:1:");
    writeText(dir + "/quat.tum", "1 0 0 0 0 0 0 0\n");
    expectTumError(dir + "/quat.tum", "quat.tum:1: quaternion");
    writeText(dir + "/extra.tum", "1 0 0 0 0 0 0 1 9\n");
    expectTumError(dir + "/extra.tum", "extra.tum:1: unexpected trailing");
    // Two poses at one time (issue 36): which one an evaluation paired depended on the line order.
    writeText(dir + "/twice.tum", "# t\n1 0 0 0 0 0 0 1\n\n1.000 2 0 0 0 0 0 1\n");
    expectTumError(dir + "/twice.tum", "twice.tum:4: timestamp 1.000 repeats line 2");
}
