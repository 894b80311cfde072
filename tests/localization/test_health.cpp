// Health checks (doc/health.md) on hand-made frame reports: each check alone, the reference.
#include <gtest/gtest.h>
#include <superloc/localization/frame_report.h>
#include <superloc/core/se3.h>
#include <superloc/localization/health.h>
#include <superloc/localization/relocalization.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <superloc/core/config.h>

#include <string>

using namespace superloc;
using namespace superloc::localization;

namespace {
FrameReport tracked(double inliers) {
    FrameReport r;
    r.converged = true;
    r.gamma = Vec6d::Constant(0.8);
    r.inlier_ratio = inliers;
    return r;
}
/// The monitor's judge() on a report, as the Localizer makes it: its state, and its reasons and
/// checks when asked.
Health classify(const HealthMonitor& h, const FrameReport& r, std::string* why = nullptr,
                HealthChecks* checks = nullptr) {
    const Verdict v = h.judge()(r);
    if (why) *why = v.reason;
    if (checks) *checks = v.checks;
    return v.health;
}
}  // namespace

TEST(Health, EachCheckAlone) {
    HealthMonitor h;
    FrameReport r = tracked(0.9);
    EXPECT_EQ(classify(h, r), Health::Ok);
    std::string why;
    r.diverged = true;
    r.diverged_reason = Divergence::NoCorrespondences;
    EXPECT_EQ(classify(h, r, &why), Health::Lost);
    EXPECT_EQ(why, "no_correspondences");
    r.diverged_reason = Divergence::JumpRejected;  // the IMU prediction was kept: degraded, not lost
    EXPECT_EQ(classify(h, r, &why), Health::Degraded);
    r = tracked(0.9);
    r.converged = false;
    r.last_step_xyz = 0.005;  // out of rounds but settling: fine
    EXPECT_EQ(classify(h, r), Health::Ok);
    r.last_step_xyz = 0.05;   // still moving
    EXPECT_EQ(classify(h, r, &why), Health::Degraded);
    EXPECT_EQ(why, "not_converged");
    r = tracked(0.9);
    r.gamma[0] = 0.25;  // below weak_gamma 0.3: an axis the scan holds weakly...
    r.gamma[5] = 0.1;
    r.cov = Mat6d::Identity() * 0.03 * 0.03;  // ...but the pose is known to 3 cm (IMU, odom_alt)
    r.cov.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * std::pow(0.2 * kDeg, 2);
    HealthChecks checks;
    EXPECT_EQ(classify(h, r, &why, &checks), Health::Ok);
    EXPECT_TRUE(checks.weak[0] && checks.weak[5] && !checks.weak[1]);  // reported all the same
    // The pose's std above [health] max_sigma_xyz (0.1 m) along any direction, or its rotation's
    // above max_sigma_deg (1 deg): degraded.
    const Eigen::Vector3d u = Eigen::Vector3d(1, 1, 0).normalized();
    r.cov.topLeftCorner<3, 3>() += 0.12 * 0.12 * u * u.transpose();
    EXPECT_EQ(classify(h, r, &why), Health::Degraded);
    EXPECT_EQ(why, "sigma_xyz");
    r.cov.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() * 0.03 * 0.03;
    r.cov(5, 5) = std::pow(1.5 * kDeg, 2);
    EXPECT_EQ(classify(h, r, &why), Health::Degraded);
    EXPECT_EQ(why, "sigma_rot");
    r = tracked(0.9);
    r.used_imu = true;
    r.pred_dxyz = 0.5;
    EXPECT_EQ(classify(h, r, &why), Health::Degraded);
    EXPECT_EQ(why, "prediction");
    r.used_imu = false;  // a constant-velocity prediction may be far off rightly
    EXPECT_EQ(classify(h, r), Health::Ok);
    // A slow drift from the gyro's rotation over [health] drift_window (1 s): above 1.5 deg.
    r = tracked(0.9);
    r.used_imu = true;
    r.imu_drift_deg = 1.4;
    EXPECT_EQ(classify(h, r), Health::Ok);
    r.imu_drift_deg = 2.0;
    EXPECT_EQ(classify(h, r, &why), Health::Degraded);
    EXPECT_EQ(why, "drift");
    r.used_imu = false;  // no gyro to compare with
    EXPECT_EQ(classify(h, r), Health::Ok);
    HealthParams off;
    off.drift_window = 0;
    r.used_imu = true;
    EXPECT_EQ(classify(HealthMonitor(off), r), Health::Ok);
}

TEST(Health, InlierChecksAreRelativeToTheRunsReference) {
    HealthMonitor h;
    FrameReport r = tracked(0.5);
    // No reference yet: a low inlier ratio alone is not judged.
    EXPECT_EQ(classify(h, r), Health::Ok);
    for (double v : {0.9, 0.92, 0.88, 0.91}) {
        FrameReport t = tracked(v);
        t.setVerdict(h.judge()(t));
        EXPECT_EQ(t.health, Health::Ok);
        h.commit(t, false);
    }
    EXPECT_NEAR(h.reference(), 0.91, 1e-9);  // median of 0.88 0.9 0.91 0.92 (upper middle)
    std::string why;
    EXPECT_EQ(classify(h, tracked(0.85)), Health::Ok);                   // > 0.9 x 0.91
    EXPECT_EQ(classify(h, tracked(0.7), &why), Health::Degraded);        // < 0.9 x, > 0.6 x
    EXPECT_EQ(why, "inliers");
    EXPECT_EQ(classify(h, tracked(0.5), &why), Health::Lost);            // < 0.6 x 0.91
    // A degraded frame does not pull the reference down.
    FrameReport low = tracked(0.7);
    low.setVerdict(h.judge()(low));
    EXPECT_EQ(low.health, Health::Degraded);
    h.commit(low, false);
    EXPECT_NEAR(h.reference(), 0.91, 1e-9);
    // Judging changes nothing of the monitor: only commit() does, once per frame.
    const FrameReport again = tracked(0.95);
    for (int k = 0; k < 5; ++k) EXPECT_EQ(h.judge()(again).health, Health::Ok);
    EXPECT_NEAR(h.reference(), 0.91, 1e-9);
}

TEST(Health, ParamsValidate) {
    HealthParams p;
    EXPECT_NO_THROW(p.validate());
    p.lost_inlier_drop = 0.95;  // above degraded_inlier_drop
    EXPECT_ANY_THROW(p.validate());
    p = HealthParams{};
    p.weak_gamma = 1.5;
    EXPECT_ANY_THROW(p.validate());
    p = HealthParams{};
    p.drift_window = -1;
    EXPECT_ANY_THROW(p.validate());
    p = HealthParams{};
    p.max_drift_deg = 0;
    EXPECT_ANY_THROW(p.validate());
    p = HealthParams{};
    p.max_sigma_xyz = 0;
    EXPECT_ANY_THROW(p.validate());
}

// The multi-frame tracking keys of [relocalization] (doc/relocalization.md §4): loaded, saved
// back, and each bad value a one-line ConfigError naming its key.
TEST(Relocalization, TrackingParamsLoadSaveValidate) {
    mrpt::config::CConfigFileMemory ini;
    ini.write("relocalization", "track_candidates", "7");
    ini.write("relocalization", "track_consistent_frames", "5");
    ini.write("relocalization", "track_probe_xyz", "1.5");
    RelocalizationParams p;
    p.loadFromConfigFile(ini, "relocalization");
    EXPECT_EQ(p.track_candidates, 7);
    EXPECT_EQ(p.track_consistent_frames, 5);
    EXPECT_DOUBLE_EQ(p.track_probe_xyz, 1.5);
    EXPECT_NO_THROW(p.validate());
    mrpt::config::CConfigFileMemory out;
    p.saveToConfigFile(out, "relocalization");
    const mrpt::config::CConfigFileMemory text(out.getContent());  // as a file would be read back
    RelocalizationParams q;
    q.loadFromConfigFile(text, "relocalization");
    EXPECT_EQ(q.track_candidates, 7);
    EXPECT_DOUBLE_EQ(q.track_ratio, p.track_ratio);
    EXPECT_EQ(q.track_max_frames, p.track_max_frames);

    const auto error = [](auto set) {
        RelocalizationParams r;
        set(r);
        try {
            r.validate();
        } catch (const superloc::ConfigError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(error([](auto& r) { r.track_candidates = -1; }).find("track_candidates"), std::string::npos);
    EXPECT_NE(error([](auto& r) { r.track_min_frames = 1; }).find("track_min_frames"), std::string::npos);
    EXPECT_NE(error([](auto& r) { r.track_ratio = 1.2; }).find("track_ratio"), std::string::npos);
    EXPECT_NE(error([](auto& r) { r.track_consistent_frames = 1; }).find("track_consistent_frames"),
              std::string::npos);
    EXPECT_NE(error([](auto& r) { r.track_lead = 0; }).find("track_lead"), std::string::npos);
    EXPECT_NE(error([](auto& r) { r.track_probe_xyz = -1; }).find("track_probe_xyz"), std::string::npos);
    EXPECT_NE(error([](auto& r) { r.track_search_every = -1; }).find("track_search_every"), std::string::npos);
    EXPECT_NE(error([](auto& r) { r.track_max_frames = 1; }).find("track_max_frames"), std::string::npos);
    EXPECT_NE(error([](auto& r) { r.track_max_ms = 0; }).find("track_max_ms"), std::string::npos);
    EXPECT_EQ(error([](auto&) {}), "");
}

// The drift check's chain on hand-made frames at 10 Hz: the gyro says the sensor turns 1 deg
// per frame about z; the solved poses follow it, then add 0.3 deg of pitch per frame (a slow
// tilt no single frame's prediction check sees). The drift over the 1 s window grows to about
// 10 x 0.3 = 3 deg; a frame that did not come from the chain starts it again.
TEST(Health, DriftAlongTheChainOfImuPredictedFrames) {
    HealthMonitor h;
    const auto rot = [](double yaw_deg, double pitch_deg) {
        SE3d T = SE3d::Identity();
        T.linear() = (Eigen::AngleAxisd(yaw_deg * M_PI / 180, Vec3d::UnitZ()) *
                      Eigen::AngleAxisd(pitch_deg * M_PI / 180, Vec3d::UnitY()))
                         .toRotationMatrix();
        return T;
    };
    SE3d prev = rot(0, 0);
    double last = 0;
    for (int k = 0; k <= 30; ++k) {
        FrameReport r = tracked(0.9);
        r.t = 0.1 * k;
        r.used_imu = k > 0;
        // The gyro's prediction: the last solved pose turned by 1 deg about its z.
        r.T_map_lidar_pred = prev * rot(1, 0);
        const double tilt = k <= 15 ? 0.0 : 0.3 * (k - 15);
        r.T_map_lidar = rot(k, tilt);
        r.imu_drift_deg = h.imuDrift(r);
        if (k < 5) {
            EXPECT_EQ(r.imu_drift_deg, 0.0) << "window not spanned yet, frame " << k;
        } else if (k <= 15) {
            EXPECT_NEAR(r.imu_drift_deg, 0.0, 1e-6) << "frame " << k;
        } else if (k == 30) {
            EXPECT_NEAR(r.imu_drift_deg, 3.0, 0.2);
        }
        h.commit(r, r.used_imu);
        prev = r.T_map_lidar;
        last = r.imu_drift_deg;
    }
    EXPECT_GT(last, HealthParams{}.max_drift_deg);
    // A relocalized frame (not chained) starts the chain again: nothing to compare for 0.5 s.
    FrameReport r = tracked(0.9);
    r.t = 3.1;
    r.used_imu = true;
    r.T_map_lidar_pred = prev * rot(1, 0);
    r.T_map_lidar = rot(31, 0);
    h.commit(r, false);
    FrameReport next = r;
    next.t = 3.2;
    next.T_map_lidar_pred = r.T_map_lidar * rot(1, 0);
    next.T_map_lidar = rot(32, 0);
    EXPECT_EQ(h.imuDrift(next), 0.0);
}

// The health checks alone make a frame's health: the Recovery hands them evidence, and each
// piece changes only what it says (an `ok` frame becomes degraded for a doubt or a tie at the
// start; a degraded one keeps its own reasons; a confirmation undoes only an "unconfirmed"). A
// frame without a pose is lost by its report (no_pose).
TEST(Health, EvidenceFromTheRecovery) {
    HealthMonitor h;
    const HealthJudge judge = h.judge();
    const Verdict ok = judge(tracked(0.9));
    ASSERT_EQ(ok.health, Health::Ok);
    FrameReport weak_rep = tracked(0.9);  // degraded for its own reason: a pose std of 20 cm
    weak_rep.cov.diagonal() << 0.2 * 0.2, 0.01 * 0.01, 0.01 * 0.01, 1e-6, 1e-6, 1e-6;
    const Verdict weak = judge(weak_rep);
    ASSERT_EQ(weak.health, Health::Degraded);

    FrameReport no_pose = tracked(0.9);
    no_pose.diverged = true;
    no_pose.diverged_reason = Divergence::NoPose;
    EXPECT_EQ(judge(no_pose).health, Health::Lost);
    EXPECT_EQ(judge(no_pose).reason, "no_pose");

    Verdict r = judge.amend(ok, HealthEvidence::Unconfirmed);
    EXPECT_EQ(r.health, Health::Degraded);
    EXPECT_EQ(r.reason, "unconfirmed");
    EXPECT_TRUE(r.checks.unconfirmed);
    r = judge.amend(r, HealthEvidence::Confirmed);
    EXPECT_EQ(r.health, Health::Ok);
    EXPECT_EQ(r.reason, "");
    EXPECT_FALSE(r.checks.unconfirmed);

    r = judge.amend(weak, HealthEvidence::Unconfirmed);
    EXPECT_EQ(r.reason, "sigma_xyz") << "a degraded frame keeps its own reasons";
    r = judge.amend(r, HealthEvidence::Confirmed);
    EXPECT_EQ(r.health, Health::Degraded) << "only an unconfirmed frame is confirmed back to ok";

    r = judge.amend(ok, HealthEvidence::StartAmbiguous);
    EXPECT_EQ(r.health, Health::Degraded);
    EXPECT_EQ(r.reason, "start_ambiguous");
    r = judge.amend(weak, HealthEvidence::StartAmbiguous);
    EXPECT_EQ(r.reason, "sigma_xyz");

    // A report put into the frame's: the verdict's fields.
    FrameReport out = tracked(0.9);
    out.setVerdict(judge.amend(ok, HealthEvidence::Unconfirmed));
    EXPECT_EQ(out.health, Health::Degraded);
    EXPECT_EQ(out.health_reason, "unconfirmed");
    EXPECT_TRUE(out.checks.unconfirmed);

    // The prediction check reads the solved pose against the prediction, as measured.
    FrameReport moved = tracked(0.9);
    moved.used_imu = true;
    moved.T_map_lidar_pred.translation() = Vec3d(0.4, 0, 0);
    moved.measurePrediction();
    EXPECT_NEAR(moved.pred_dxyz, 0.4, 1e-12);
    EXPECT_EQ(judge(moved).reason, "prediction");
}
