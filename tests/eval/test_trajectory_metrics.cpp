#include <gtest/gtest.h>
#include <superloc/core/se3.h>
#include <superloc/eval/evaluation.h>

#include <cmath>
#include <nlohmann/json.hpp>

using namespace superloc;
using namespace superloc::eval;

namespace {
/// n poses along x, 1 m apart, 0.1 s apart, no rotation.
Trajectory line(size_t n) {
    Trajectory t;
    for (size_t i = 0; i < n; ++i)
        t.push_back({0.1 * double(i), makePoseRPY(double(i), 0, 0, 0, 0, 0), {}});
    return t;
}
/// n poses on a circle of radius 5 m, heading along the tangent, with some height change.
Trajectory circle(size_t n) {
    Trajectory t;
    for (size_t i = 0; i < n; ++i) {
        const double a = 2 * M_PI * double(i) / double(n);
        t.push_back({0.1 * double(i),
                     makePoseRPY(5 * std::cos(a), 5 * std::sin(a), 0.3 * std::sin(3 * a), 0, 0,
                                 a + M_PI / 2),
                     {}});
    }
    return t;
}
const double kFullArea = 1 - std::exp(-10.0);  // area of F1 = 1 over tau in [e^-10, 1]
}  // namespace

TEST(Association, NearestWithinToleranceOneToOne) {
    Trajectory gt = line(5);  // t = 0, .1, .2, .3, .4
    Trajectory est;
    for (double t : {0.004, 0.098, 0.101, 0.25, 0.41}) est.push_back({t, SE3d::Identity(), {}});
    const Association a = associate(est, gt, 0.02);
    // 0.004->0; 0.098 and 0.101 both want 1: 0.101 (|dt| .001) wins; 0.25 is .05 from both: none.
    ASSERT_EQ(a.pairs.size(), 3u);
    EXPECT_EQ(a.pairs[0], (std::pair<size_t, size_t>{0, 0}));
    EXPECT_EQ(a.pairs[1], (std::pair<size_t, size_t>{2, 1}));
    EXPECT_EQ(a.pairs[2], (std::pair<size_t, size_t>{4, 4}));
    EXPECT_EQ(a.gt_of_est[1], SIZE_MAX);
    EXPECT_EQ(a.gt_of_est[3], SIZE_MAX);
}

TEST(ErrorStats, HandComputed) {
    const ErrorStats s = errorStats({3, 4});
    EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(12.5));
    EXPECT_DOUBLE_EQ(s.mean, 3.5);
    EXPECT_DOUBLE_EQ(s.median, 3.5);
    EXPECT_DOUBLE_EQ(s.max, 4.0);
    EXPECT_DOUBLE_EQ(errorStats({5, 1, 3}).median, 3.0);
}

TEST(Metrics, IdenticalInputsGiveZeroErrorAndFullRobustness) {
    const Trajectory gt = circle(40);
    const EvalResult r = evaluate(gt, gt, EvalParams{});
    EXPECT_EQ(r.matched_frames, 40u);
    EXPECT_NEAR(r.ate.trans.rmse, 0, 1e-12);
    EXPECT_NEAR(r.ate.rot.max, 0, 1e-7);
    EXPECT_NEAR(r.rpe.trans.max, 0, 1e-12);
    EXPECT_NEAR(r.rp.area, kFullArea, 1e-12);
    EXPECT_NEAR(r.rr.area, kFullArea, 1e-12);
}

// Offset (0.1, 0.2, -0.2): |offset| = sqrt(0.01 + 0.04 + 0.04) = 0.3 m on every pose; the
// relative motion is unchanged, so RPE = 0 and robustness is full.
TEST(Metrics, ConstantOffsetGivesItsNormAsAte) {
    const Trajectory gt = circle(30);
    Trajectory est = gt;
    for (auto& p : est) p.pose.pretranslate(Vec3d(0.1, 0.2, -0.2));
    const EvalResult r = evaluate(est, gt, EvalParams{});
    EXPECT_NEAR(r.ate.trans.rmse, 0.3, 1e-12);
    EXPECT_NEAR(r.ate.trans.mean, 0.3, 1e-12);
    EXPECT_NEAR(r.ate.trans.max, 0.3, 1e-12);
    EXPECT_NEAR(r.rpe.trans.max, 0, 1e-12);
    EXPECT_NEAR(r.rp.area, kFullArea, 1e-12);
}

// With alignment, a rigidly moved estimate (yaw 30 deg, t = (1, 2, 3)) has zero ATE.
TEST(Metrics, Se3AlignmentRemovesARigidMotion) {
    const Trajectory gt = circle(30);
    const SE3d T = makePoseRPY(1, 2, 3, 0, 0, M_PI / 6);
    Trajectory est = gt;
    for (auto& p : est) p.pose = T * p.pose;
    EvalParams prm;
    EXPECT_GT(evaluate(est, gt, prm).ate.trans.rmse, 1.0);
    prm.align = true;
    const EvalResult r = evaluate(est, gt, prm);
    EXPECT_NEAR(r.ate.trans.max, 0, 1e-9);
    EXPECT_NEAR(r.ate.rot.max, 0, 1e-7);
    EXPECT_TRUE(r.ate.T_gt_est.isApprox(T.inverse(), 1e-9));
}

// GT 21 frames (20 steps); the run stops after 11 frames (10 steps, all exact):
// precision 10/10 = 1, recall 10/20 = 0.5, F1 = 2*1*0.5/1.5 = 2/3 at every tau.
TEST(Robustness, RunStoppingHalfwayHasRecallHalf) {
    const Trajectory gt = line(21);
    const Trajectory est(gt.begin(), gt.begin() + 11);
    const EvalResult r = evaluate(est, gt, EvalParams{});
    const F1Point p = f1At(r.rpe.frame_trans, 20, 0.01);
    EXPECT_DOUBLE_EQ(p.precision, 1.0);
    EXPECT_DOUBLE_EQ(p.recall, 0.5);
    EXPECT_NEAR(p.f1, 2.0 / 3.0, 1e-12);
    EXPECT_NEAR(r.rp.area, 2.0 / 3.0 * kFullArea, 1e-12);
    EXPECT_NEAR(r.ate.trans.rmse, 0, 1e-12);  // what it did estimate is exact
}

// Frame 5 of 11 displaced by 0.1 m along x: steps 4->5 and 5->6 have RPE 0.1 m, the other 8 are
// exact. At tau = 0.05: 8 inliers of 10 estimated and 10 GT steps -> P = R = F1 = 0.8.
// Area (100 bins): bins with midpoint tau >= 0.1, i.e. T_mid = (k + .5)/100 <= ln(10)/10 = 0.2303,
// are k = 0..22 with F1 = 1, covering tau in [e^-2.3, 1]; the rest has F1 = 0.8:
// Rp = (1 - e^-2.3) + 0.8 (e^-2.3 - e^-10).
TEST(Robustness, HandComputedAreaWithTwoBadSteps) {
    const Trajectory gt = line(11);
    Trajectory est = gt;
    est[5].pose.pretranslate(Vec3d(0.1, 0, 0));
    const EvalResult r = evaluate(est, gt, EvalParams{});
    ASSERT_EQ(r.rpe.frame_trans.size(), 10u);
    EXPECT_NEAR(r.rpe.frame_trans[4], 0.1, 1e-12);
    EXPECT_NEAR(r.rpe.frame_trans[5], 0.1, 1e-12);
    EXPECT_NEAR(r.rpe.trans.max, 0.1, 1e-12);
    const F1Point p = f1At(r.rpe.frame_trans, 10, 0.05);
    EXPECT_NEAR(p.f1, 0.8, 1e-12);
    EXPECT_NEAR(r.rp.area, (1 - std::exp(-2.3)) + 0.8 * (std::exp(-2.3) - std::exp(-10.0)), 1e-12);
    EXPECT_NEAR(r.rr.area, kFullArea, 1e-12);  // no rotation error
    EXPECT_NEAR(r.ate.trans.max, 0.1, 1e-12);
}

// An estimate with no GT counterpart in time is never an inlier but still counts as estimated.
TEST(Robustness, UnmatchedFramesLosePrecision) {
    const Trajectory gt = line(11);
    Trajectory est = gt;
    est[10].t += 1.0;  // far from any GT time
    const EvalResult r = evaluate(est, gt, EvalParams{});
    EXPECT_EQ(r.matched_frames, 10u);
    EXPECT_TRUE(std::isnan(r.rpe.frame_trans[9]));
    const F1Point p = f1At(r.rpe.frame_trans, 10, 0.5);
    EXPECT_DOUBLE_EQ(p.precision, 0.9);
    EXPECT_DOUBLE_EQ(p.recall, 0.9);
}

TEST(Timing, HandComputedPercentiles) {
    std::vector<double> ms;
    for (int i = 20; i >= 1; --i) ms.push_back(i);
    const TimingStats s = timingStats(ms);
    EXPECT_DOUBLE_EQ(s.median_ms, 10.5);
    EXPECT_DOUBLE_EQ(s.p95_ms, 19.0);  // nearest rank: ceil(0.95 * 20) = 19th value
    EXPECT_DOUBLE_EQ(s.max_ms, 20.0);
    EXPECT_DOUBLE_EQ(s.mean_ms, 10.5);
    EXPECT_NEAR(s.fps, 1000 / 10.5, 1e-9);
    EXPECT_EQ(timingStats({}).frames, 0u);
}

TEST(Timing, MedianAndNearestRankPercentile) {
    EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2.0);
    EXPECT_DOUBLE_EQ(median({4, 1, 3, 2}), 2.5);
    EXPECT_DOUBLE_EQ(percentile({1, 2, 3, 4, 5}, 0.95), 5.0);  // ceil(4.75) = 5th value
    EXPECT_DOUBLE_EQ(percentile({1, 2, 3, 4, 5}, 0.5), 3.0);
    EXPECT_DOUBLE_EQ(percentile({5, 4, 3, 2, 1}, 0.2), 1.0);
    EXPECT_DOUBLE_EQ(percentile({}, 0.5), 0.0);
    EXPECT_DOUBLE_EQ(median({}), 0.0);
}

// An estimate far from GT in time matches nothing: no ATE, zero robustness, said in the summary.
TEST(Metrics, NoMatchedFrames) {
    const Trajectory gt = line(5);
    Trajectory est = gt;
    for (auto& p : est) p.t += 100;
    const EvalResult r = evaluate(est, gt, EvalParams{});
    EXPECT_EQ(r.matched_frames, 0u);
    EXPECT_DOUBLE_EQ(r.rp.area, 0.0);
    EXPECT_NE(summaryMarkdown(r).find("no estimate within the time tolerance"), std::string::npos);
    EXPECT_DOUBLE_EQ(evaluate({}, gt, EvalParams{}).rr.area, 0.0);
}

// Risk as a failure predictor, hand-counted. Ten frames heading +90 deg yaw (body x = map y):
// frames 0-4 are 0.3 m off along map y, i.e. along body x (failed along x); frame 9 is 2 deg
// off in yaw. Rule labels1 flags x on frames 0, 1, 2 and 5: x: tp 3, fp 1, fn 2, tn 4 ->
// precision 0.75, recall 0.6. Rule eigen flags yaw on frame 9 only: yaw precision = recall = 1.
// Rule labels2 flags nothing: precision undefined, recall 0 on x.
TEST(RiskPrediction, HandCounted) {
    Trajectory gt, est;
    eval::FrameLog log;
    for (int i = 0; i < 10; ++i) {
        gt.push_back({0.1 * i, makePoseRPY(i, 0, 0, 0, 0, M_PI / 2), {}});
        est.push_back({0.1 * i, makePoseRPY(i, i < 5 ? 0.3 : 0.0, 0, 0, 0, M_PI / 2 + (i == 9 ? 2 * kDeg : 0)), {}});
        eval::FrameRecord f;
        f.t = 0.1 * i;
        f.rule_flags[0][0] = i <= 2 || i == 5;
        f.rule_flags[2][5] = i == 9;
        log.frames.push_back(f);
    }
    log.has_rules = true;
    const EvalParams prm;
    const RiskPrediction p = riskPrediction(est, gt, log, prm);
    EXPECT_EQ(p.frames, 10u);
    const auto& x = p.counts[0][0];
    EXPECT_EQ(x.tp, 3u);
    EXPECT_EQ(x.fp, 1u);
    EXPECT_EQ(x.fn, 2u);
    EXPECT_EQ(x.tn, 4u);
    EXPECT_DOUBLE_EQ(x.precision(), 0.75);
    EXPECT_DOUBLE_EQ(x.recall(), 0.6);
    // Nothing failed along y (body y = map -x) or z.
    EXPECT_EQ(p.counts[0][1].tp + p.counts[0][1].fn, 0u);
    EXPECT_TRUE(std::isnan(p.counts[0][1].recall()));
    EXPECT_DOUBLE_EQ(p.counts[2][5].precision(), 1.0);
    EXPECT_DOUBLE_EQ(p.counts[2][5].recall(), 1.0);
    EXPECT_TRUE(std::isnan(p.counts[1][0].precision()));
    EXPECT_DOUBLE_EQ(p.counts[1][0].recall(), 0.0);
    // Sums over runs; the Markdown and JSON forms carry the same numbers.
    RiskPrediction twice = p;
    twice += p;
    EXPECT_EQ(twice.counts[0][0].tp, 6u);
    EXPECT_EQ(twice.frames, 20u);
    EXPECT_NE(riskPredictionMarkdown(p).find("| γ, 1 rotation label | 0.75 / 0.60 |"), std::string::npos)
        << riskPredictionMarkdown(p);
    const auto j = toJson(p);
    EXPECT_EQ(j["flags_labels1"]["x"]["fn"].get<size_t>(), 2u);
    EXPECT_DOUBLE_EQ(j["flags_labels1"]["x"]["precision"].get<double>(), 0.75);
    EXPECT_TRUE(j["flags_labels2"]["x"]["precision"].is_null());  // nothing flagged
}
