#include <superloc/core/se3.h>
#include <superloc/eval/evaluation.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

namespace superloc::eval {

HealthConfusion healthConfusion(const Trajectory& est, const Trajectory& gt, const FrameLog& frames,
                                double assoc_tolerance) {
    HealthConfusion c;
    const Association a = associate(est, gt, assoc_tolerance);
    const size_t n = std::min(est.size(), frames.frames.size());
    for (size_t i = 0; i < n; ++i) {
        const std::string& h = frames.frames[i].health;
        const size_t state = h == "ok" ? 0 : h == "degraded" ? 1 : 2;
        if (i >= a.gt_of_est.size() || a.gt_of_est[i] == SIZE_MAX) {
            ++c.unmatched;
            continue;
        }
        const SE3d& T = est[i].pose;
        const SE3d& G = gt[a.gt_of_est[i]].pose;
        const double dxyz = translationDistance(T, G);
        const double ddeg = rotationAngle(T, G) * 180.0 / M_PI;
        const size_t bucket = dxyz > 0.5 || ddeg > 5.0 ? 2 : dxyz >= 0.1 ? 1 : 0;
        c.counts[state][bucket]++;
    }
    return c;
}

Consistency consistency(const Trajectory& est, const Trajectory& gt, const FrameLog& frames, double assoc_tolerance) {
    Consistency c;
    c.full = frames.has_cov6;
    const Association a = associate(est, gt, assoc_tolerance);
    const size_t n = std::min(est.size(), frames.frames.size());
    size_t in_pos = 0, in_rot = 0, in_pose = 0;
    for (size_t i = 0; i < n; ++i) {
        const FrameRecord& f = frames.frames[i];
        if (f.health == "lost" || !f.cov_pos || i >= a.gt_of_est.size() || a.gt_of_est[i] == SIZE_MAX) continue;
        const SE3d& T = est[i].pose;
        const SE3d& G = gt[a.gt_of_est[i]].pose;
        const Vec3d ep = T.translation() - G.translation();
        const Vec3d er_map = logSO3(T.linear() * G.linear().transpose());
        Mat6d C;
        if (f.cov6) {
            C = *f.cov6;
        } else {
            // Rotation about the pose's own axes, diagonal: turned into the map's.
            const Mat3d R = T.linear();
            C.setZero();
            C.topLeftCorner<3, 3>() = *f.cov_pos;
            C.bottomRightCorner<3, 3>() = R * (f.sigma_rot_deg->array() * kDeg).square().matrix().asDiagonal() * R.transpose();
        }
        const auto nees = [](const Eigen::MatrixXd& Cm, const Eigen::VectorXd& e) {
            const Eigen::LDLT<Eigen::MatrixXd> ldlt{Cm};
            if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0))
                return std::numeric_limits<double>::infinity();
            return double(e.dot(ldlt.solve(e)));
        };
        if (!(C.topLeftCorner<3, 3>().trace() > 0)) continue;  // a frame without a covariance
        c.t.push_back(est[i].t);
        c.pos.push_back(nees(C.topLeftCorner<3, 3>(), ep));
        c.rot.push_back(nees(C.bottomRightCorner<3, 3>(), er_map));
        in_pos += c.pos.back() <= kChi2_3dof_95;
        in_rot += c.rot.back() <= kChi2_3dof_95;
        if (c.full) {
            Vec6d e;
            e << ep, er_map;
            c.pose.push_back(nees(C, e));
            in_pose += c.pose.back() <= kChi2_6dof_95;
        }
    }
    const auto mean = [](const std::vector<double>& v) {
        double s = 0;
        for (double x : v) s += x;
        return v.empty() ? 0.0 : s / double(v.size());
    };
    c.anees_pos = mean(c.pos), c.anees_rot = mean(c.rot), c.anees_pose = mean(c.pose);
    const double nf = std::max<double>(1, double(c.pos.size()));
    c.under95_pos = in_pos / nf, c.under95_rot = in_rot / nf, c.under95_pose = c.full ? in_pose / nf : 0;
    return c;
}

io::Json toJson(const Consistency& c, bool with_series) {
    io::Json j = {{"frames", c.frames()},
                  {"full_6x6", c.full},
                  {"anees_position", c.anees_pos},
                  {"anees_rotation", c.anees_rot},
                  {"under95_position", c.under95_pos},
                  {"under95_rotation", c.under95_rot}};
    if (c.full) {
        j["anees_pose"] = c.anees_pose;
        j["under95_pose"] = c.under95_pose;
    }
    if (with_series) {
        j["t"] = c.t;
        j["nees_position"] = c.pos;
        j["nees_rotation"] = c.rot;
        if (c.full) j["nees_pose"] = c.pose;
    }
    return j;
}

double RiskPrediction::Counts::precision() const {
    return tp + fp > 0 ? double(tp) / double(tp + fp) : std::numeric_limits<double>::quiet_NaN();
}
double RiskPrediction::Counts::recall() const {
    return tp + fn > 0 ? double(tp) / double(tp + fn) : std::numeric_limits<double>::quiet_NaN();
}
RiskPrediction::Counts& RiskPrediction::Counts::operator+=(const Counts& o) {
    tp += o.tp, fp += o.fp, fn += o.fn, tn += o.tn;
    return *this;
}
RiskPrediction& RiskPrediction::operator+=(const RiskPrediction& o) {
    for (int r = 0; r < kRules; ++r)
        for (int k = 0; k < 6; ++k) counts[r][k] += o.counts[r][k];
    frames += o.frames;
    return *this;
}

RiskPrediction riskPrediction(const Trajectory& est, const Trajectory& gt, const FrameLog& frames,
                              const EvalParams& params) {
    RiskPrediction p;
    const Association a = associate(est, gt, params.assoc_tolerance);
    const size_t n = std::min(est.size(), frames.frames.size());
    const double fail_rad = params.risk_fail_deg * kDeg;
    for (size_t i = 0; i < n; ++i) {
        if (i >= a.gt_of_est.size() || a.gt_of_est[i] == SIZE_MAX) continue;
        const SE3d E = gt[a.gt_of_est[i]].pose.inverse() * est[i].pose;
        const Eigen::AngleAxisd aa(E.linear());
        Vec6d err;
        err << E.translation().cwiseAbs(), (aa.angle() * aa.axis()).cwiseAbs();
        if (!err.allFinite()) continue;
        ++p.frames;
        for (int k = 0; k < 6; ++k) {
            const bool failed = err[k] > (k < 3 ? params.risk_fail_xyz : fail_rad);
            for (int r = 0; r < kRules; ++r) {
                const bool flagged = frames.frames[i].rule_flags[r][k];
                auto& c = p.counts[r][k];
                (flagged ? (failed ? c.tp : c.fp) : (failed ? c.fn : c.tn))++;
            }
        }
    }
    return p;
}

EvalResult evaluate(const Trajectory& est, const Trajectory& gt, const EvalParams& params,
                    const PointCloud* est_map, const PointCloud* gt_map, const FrameLog* frames) {
    EvalResult r;
    r.est_frames = est.size();
    r.gt_frames = gt.size();
    const Association a = associate(est, gt, params.assoc_tolerance);
    r.matched_frames = a.pairs.size();
    r.aligned = params.align;
    r.ate = computeAte(est, gt, a, params.align);
    r.rpe = computeRpe(est, gt, a);
    // Robustness over steps: est.size()-1 estimated steps, gt.size()-1 GT steps.
    const size_t gt_steps = gt.empty() ? 0 : gt.size() - 1;
    r.rp = robustnessArea(r.rpe.frame_trans, gt_steps, params.robustness_bins);
    r.rr = robustnessArea(r.rpe.frame_rot, gt_steps, params.robustness_bins);
    if (est_map && gt_map)
        r.map = computeMapOutliers(*est_map, *gt_map, params.map_voxel, params.outlier_threshold);
    if (frames && !frames->frames.empty()) {
        for (const auto& [name, ms] : frames->stage_ms) r.stages[name] = timingStats(ms);
        if (r.stages.count("ms_total")) r.timing = r.stages.at("ms_total");
        size_t flagged = 0;
        for (const auto& f : frames->frames)
            for (bool d : f.degenerate)
                if (d) {
                    ++flagged;
                    break;
                }
        r.degenerate_frame_percent = 100.0 * double(flagged) / double(frames->frames.size());
        if (frames->has_health) r.health = healthConfusion(est, gt, *frames, params.assoc_tolerance);
        if (frames->has_rules) r.risk = riskPrediction(est, gt, *frames, params);
        if (frames->has_cov) r.consistency = consistency(est, gt, *frames, params.assoc_tolerance);
    }
    return r;
}

namespace {
io::Json stats(const ErrorStats& s) {
    return {{"n", s.n}, {"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"max", s.max}};
}
io::Json timing(const TimingStats& t) {
    return {{"frames", t.frames}, {"mean_ms", t.mean_ms}, {"median_ms", t.median_ms},
            {"p95_ms", t.p95_ms}, {"max_ms", t.max_ms},   {"fps", t.fps}};
}
io::Json curve(const RobustnessCurve& c) {
    std::vector<double> tau, f1;
    for (const auto& p : c.curve) tau.push_back(p.tau), f1.push_back(p.f1);
    return {{"area", c.area}, {"tau", tau}, {"f1", f1}};
}
io::Json finiteOrNull(double v) { return std::isfinite(v) ? io::Json(v) : io::Json(nullptr); }
std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}
}  // namespace

std::string riskPredictionMarkdown(const RiskPrediction& p) {
    std::string s = "| rule |";
    for (int k = 0; k < 6; ++k) s += std::string(" ") + kAxisNames[k] + " |";
    s += "\n|---|";
    for (int k = 0; k < 6; ++k) s += "---:|";
    s += "\n";
    const auto ratio = [](double v) { return std::isfinite(v) ? fmt("%.2f", v) : std::string("–"); };
    for (int r = 0; r < kRules; ++r) {
        s += std::string("| ") + kRuleNames[r] + " |";
        for (int k = 0; k < 6; ++k) {
            const auto& c = p.counts[r][k];
            s += " " + ratio(c.precision()) + " / " + ratio(c.recall()) + " |";
        }
        s += "\n";
    }
    return s;
}

io::Json toJson(const RiskPrediction& p) {
    io::Json j = {{"frames", p.frames}};
    for (int r = 0; r < kRules; ++r) {
        io::Json rule = io::Json::object();
        for (int k = 0; k < 6; ++k) {
            const auto& c = p.counts[r][k];
            rule[kAxisNames[k]] = {{"tp", c.tp},
                                   {"fp", c.fp},
                                   {"fn", c.fn},
                                   {"tn", c.tn},
                                   // undefined (nothing flagged / nothing failed): null
                                   {"precision", finiteOrNull(c.precision())},
                                   {"recall", finiteOrNull(c.recall())}};
        }
        j[kRuleColumns[r]] = rule;
    }
    return j;
}

io::Json toJson(const EvalResult& r, bool with_curves) {
    io::Json j = {{"est_frames", r.est_frames},
                        {"gt_frames", r.gt_frames},
                        {"matched_frames", r.matched_frames},
                        {"aligned", r.aligned},
                        {"ate", {{"trans_m", stats(r.ate.trans)}, {"rot_rad", stats(r.ate.rot)}}},
                        {"rpe", {{"trans_m", stats(r.rpe.trans)}, {"rot_rad", stats(r.rpe.rot)}}},
                        {"Rp", r.rp.area},
                        {"Rr", r.rr.area}};
    if (with_curves) {
        j["f1_trans"] = curve(r.rp);
        j["f1_rot"] = curve(r.rr);
    }
    if (r.map)
        j["map"] = {{"points", r.map->points},
                    {"gt_points", r.map->gt_points},
                    {"outlier_percent", r.map->outlier_percent},
                    {"median_dist_m", r.map->median_dist},
                    {"mean_dist_m", r.map->mean_dist}};
    if (r.timing) j["timing"] = timing(*r.timing);
    if (!r.stages.empty()) {
        io::Json stages = io::Json::object();
        for (const auto& [name, t] : r.stages) stages[name] = timing(t);
        j["stages"] = stages;
    }
    if (r.degenerate_frame_percent) j["degenerate_frame_percent"] = *r.degenerate_frame_percent;
    if (r.health) {
        io::Json h = io::Json::object();
        for (int s = 0; s < 3; ++s)
            h[kHealthStates[s]] = {{"err_lt_0.1m", r.health->counts[s][0]},
                                   {"err_0.1_0.5m", r.health->counts[s][1]},
                                   {"err_gt_0.5m_or_5deg", r.health->counts[s][2]}};
        h["unmatched"] = r.health->unmatched;
        h["confidently_wrong"] = r.health->confidentlyWrong();
        j["health"] = h;
    }
    if (r.risk) j["risk_prediction"] = toJson(*r.risk);
    if (r.consistency) j["consistency"] = toJson(*r.consistency, with_curves);
    return j;
}

std::string summaryMarkdown(const EvalResult& r) {
    std::string s = "| metric | value |\n|---|---|\n";
    auto row = [&](const std::string& k, const std::string& v) {
        s += "| " + k + " | " + v + " |\n";
    };
    row("frames (estimate / GT / matched)", std::to_string(r.est_frames) + " / " +
                                                std::to_string(r.gt_frames) + " / " +
                                                std::to_string(r.matched_frames));
    if (r.matched_frames == 0) {
        row("ATE, RPE", "– (no estimate within the time tolerance of a GT pose)");
        row("Rp / Rr", "0.0000 / 0.0000");
        return s;
    }
    row(std::string("ATE trans RMSE / mean / max [m]") + (r.aligned ? " (SE(3)-aligned)" : ""),
        fmt("%.4f", r.ate.trans.rmse) + " / " + fmt("%.4f", r.ate.trans.mean) + " / " +
            fmt("%.4f", r.ate.trans.max));
    row("ATE rot RMSE [deg]", fmt("%.3f", r.ate.rot.rmse * 180 / M_PI));
    row("RPE (1 frame) trans RMSE [m] / rot RMSE [deg]",
        fmt("%.4f", r.rpe.trans.rmse) + " / " + fmt("%.3f", r.rpe.rot.rmse * 180 / M_PI));
    row("Rp / Rr", fmt("%.4f", r.rp.area) + " / " + fmt("%.4f", r.rr.area));
    if (r.map)
        row("map outliers [%] / median dist [m] (" + std::to_string(r.map->points) + " pts)",
            fmt("%.2f", r.map->outlier_percent) + " / " + fmt("%.4f", r.map->median_dist));
    if (r.timing)
        row("ms/frame median / p95 / max, FPS",
            fmt("%.1f", r.timing->median_ms) + " / " + fmt("%.1f", r.timing->p95_ms) + " / " +
                fmt("%.1f", r.timing->max_ms) + ", " + fmt("%.1f", r.timing->fps));
    if (r.degenerate_frame_percent)
        row("frames with a degenerate axis [%]", fmt("%.1f", *r.degenerate_frame_percent));
    if (r.health) {
        for (int st = 0; st < 3; ++st) {
            const auto& c = r.health->counts[st];
            row(std::string("health ") + kHealthStates[st] + ": frames < 0.1 m / 0.1-0.5 m / > 0.5 m or 5 deg",
                std::to_string(c[0]) + " / " + std::to_string(c[1]) + " / " + std::to_string(c[2]));
        }
    }
    if (r.consistency) {
        const auto& c = *r.consistency;
        row("consistency: frames / ANEES position, rotation" + std::string(c.full ? ", pose" : "") +
                " (dof 3, 3" + (c.full ? ", 6" : "") + ")",
            std::to_string(c.frames()) + " / " + fmt("%.2f", c.anees_pos) + ", " + fmt("%.2f", c.anees_rot) +
                (c.full ? ", " + fmt("%.2f", c.anees_pose) : ""));
        row("consistency: frames under the chi-square 95 % bound [%] position, rotation" +
                std::string(c.full ? ", pose" : ""),
            fmt("%.1f", 100 * c.under95_pos) + ", " + fmt("%.1f", 100 * c.under95_rot) +
                (c.full ? ", " + fmt("%.1f", 100 * c.under95_pose) : ""));
    }
    if (r.risk)
        s += "\nRisk as a failure predictor (" + std::to_string(r.risk->frames) +
             " frames; per axis the precision / recall of each rule's flag for an error above "
             "[eval] risk_fail_xyz / risk_fail_deg along that axis):\n\n" +
             riskPredictionMarkdown(*r.risk);
    return s;
}

}  // namespace superloc::eval
