// odom_alt's systematic error learned on held axes (fusion::OdomCalibration, doc/method.md §2): the fit.
#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/fusion/odom_calibration.h>

#include "odom_test_motion.h"

#include <array>
#include <cmath>
#include <random>

using namespace superloc;
using namespace superloc::fusion;
using superloc::testing::all;
using superloc::testing::odometer;
using superloc::testing::trueMotion;

TEST(OdomCalibration, LearnsDriftScaleAndSlipWhereHeld) {
    std::mt19937 rng(7);
    const Vec3d b(0.015, -0.01, 0.008);  // 2 %/m in a fixed body direction (the simulator's model)
    const double s = 0.02, c = 3.0 * M_PI / 180;  // 2 % rotation scale, 3 deg/m heading slip
    OdomCalibration cal;
    for (int k = 0; k < 200; ++k) {
        const SE3d m = trueMotion(k);
        cal.update(odometer(m, b, s, c, 0.0005, 0.0002, rng), m, all());
    }
    for (int k = 0; k < 6; ++k) EXPECT_TRUE(cal.calibrated(k)) << k;
    EXPECT_LT((cal.drift() - b).norm(), 5e-4) << cal.drift().transpose();  // of 0.02
    EXPECT_NEAR(cal.rotationScale().z(), s, 5e-3);  // yaw turns enough to see its scale
    EXPECT_NEAR(cal.rotationPerM().z(), c, 2e-3);
    // The correction leaves the white noise: over fresh frames, the corrected motion is within a
    // few noise sigmas of the truth where the raw one is centimetres off.
    double raw = 0, corrected = 0;
    for (int k = 200; k < 260; ++k) {
        const SE3d m = trueMotion(k);
        const SE3d o = odometer(m, b, s, c, 0.0005, 0.0002, rng);
        raw = std::max(raw, translationDistance(o, m));
        corrected = std::max(corrected, translationDistance(cal.correct(o), m));
        EXPECT_LT(rotationAngle(cal.correct(o), m), 1.5e-3) << k;
    }
    EXPECT_GT(raw, 0.008);
    EXPECT_LT(corrected, 0.003);
    // Its per-frame std: the noise left (0.5 mm per axis, the estimate taken as exact here).
    const Vec6d sig = cal.sigma(trueMotion(0));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(sig[k], 0.0005, 0.0002) << k;
}

TEST(OdomCalibration, AxesNotHeldAreNotLearned) {
    std::mt19937 rng(3);
    OdomCalibration cal;
    std::array<bool, 6> held = all();
    held[0] = false;  // x: the corridor's axis
    for (int k = 0; k < 100; ++k) {
        const SE3d m = trueMotion(k);
        cal.update(odometer(m, Vec3d(0.02, 0.01, 0), 0, 0, 0.0005, 0.0002, rng), m, held);
    }
    EXPECT_FALSE(cal.calibrated(0));
    EXPECT_TRUE(cal.calibrated(1));
    EXPECT_TRUE(std::isnan(cal.sigma(trueMotion(0))[0]));
    EXPECT_NEAR(cal.drift().y(), 0.01, 3e-4);
    // x is left as odom_alt reports it; y is corrected.
    const SE3d m = trueMotion(5), o = odometer(m, Vec3d(0.02, 0.01, 0), 0, 0, 0, 0, rng);
    EXPECT_NEAR(cal.correct(o).translation().x(), o.translation().x(), 1e-12);
    EXPECT_NEAR(cal.correct(o).translation().y(), m.translation().y(), 3e-4);
}

TEST(OdomCalibration, JumpIsAnOutlierNotLearned) {
    std::mt19937 rng(5);
    OdomCalibration cal;
    const Vec3d b(0.02, 0, 0);
    for (int k = 0; k < 100; ++k) {
        const SE3d m = trueMotion(k);
        cal.update(odometer(m, b, 0, 0, 0.0005, 0.0002, rng), m, all());
    }
    const Vec3d before = cal.drift();
    const SE3d m = trueMotion(100);
    SE3d jumped = odometer(m, b, 0, 0, 0.0005, 0.0002, rng);
    jumped.translation() += Vec3d(0.3, -0.2, 0.1);  // a VIO re-localizing: not in its covariance
    const auto outlier = cal.update(jumped, m, all());
    EXPECT_TRUE(outlier[0] && outlier[1] && outlier[2]);
    EXPECT_EQ(cal.outliers()[0], 1);
    EXPECT_LT((cal.drift() - before).norm(), 1e-9);
}

TEST(OdomCalibration, ForgetsWithTheDistanceTravelled) {
    std::mt19937 rng(9);
    OdomCalibrationParams p;
    p.memory_m = 20;  // a short memory: 40 frames of 0.5 m
    OdomCalibration cal(p);
    for (int k = 0; k < 200; ++k) {
        const SE3d m = trueMotion(k);
        const Vec3d b = k < 100 ? Vec3d(0.02, 0, 0) : Vec3d(0.005, 0, 0);  // the tyre pressure changed
        // The change is far outside the fit's noise at first: the outlier test would skip it
        // forever; an odometer whose scale really changed must still be followed.
        cal.update(odometer(m, b, 0, 0, 0.0005, 0.0002, rng), m, all());
    }
    EXPECT_NEAR(cal.drift().x(), 0.005, 1e-3);
}

// Without the correction (apply_correction = false, the baselines' covariance): the motion is
// left as it is, and what the blocks measure is the raw error. A fixed drift of 2 %/m then keeps
// its sign over every block, so a blind stretch's per-frame variances sum to the drift's square
// over it, (0.02 D)^2, where the calibrated odometry's stay at the noise's.
