#include <superloc/core/se3.h>
#include <superloc/app/bench_report.h>
#include <superloc/io/json_file.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <set>

namespace superloc::app {
namespace {

const RunRecord* find(const std::vector<RunRecord>& runs, const std::string& seq,
                      const std::string& m) {
    for (const auto& r : runs)
        if (r.sequence == seq && r.method == m) return &r;
    return nullptr;
}

struct Metric {
    std::string title;
    const char* format;
    int better;  ///< -1 lower is better, +1 higher, 0 no ranking
    std::function<std::optional<double>(const RunRecord&)> get;
};

std::vector<Metric> metrics(double outlier_threshold) {
    char thr[64];
    std::snprintf(thr, sizeof thr, "Map outliers [%%] (farther than %.0f cm from the GT map)",
                  100 * outlier_threshold);
    return {
        {thr, "%.2f", -1,
         [](const RunRecord& r) -> std::optional<double> {
             if (r.result && r.result->map) return r.result->map->outlier_percent;
             return std::nullopt;
         }},
        {"ATE RMSE [m] (map frame, no alignment)", "%.3f", -1,
         [](const RunRecord& r) -> std::optional<double> {
             if (r.result && r.result->matched_frames) return r.result->ate.trans.rmse;
             return std::nullopt;
         }},
        {"Robustness Rp (translation)", "%.3f", +1,
         [](const RunRecord& r) -> std::optional<double> {
             if (r.result) return r.result->rp.area;
             return std::nullopt;
         }},
        {"Robustness Rr (rotation)", "%.3f", +1,
         [](const RunRecord& r) -> std::optional<double> {
             if (r.result) return r.result->rr.area;
             return std::nullopt;
         }},
        {"ms per frame (median)", "%.1f", -1,
         [](const RunRecord& r) -> std::optional<double> {
             if (r.result && r.result->timing) return r.result->timing->median_ms;
             return std::nullopt;
         }},
        {"Frames with a degenerate axis [%] (risk module's flags)", "%.1f", 0,
         [](const RunRecord& r) -> std::optional<double> {
             if (r.result && r.result->degenerate_frame_percent)
                 return *r.result->degenerate_frame_percent;
             return std::nullopt;
         }},
    };
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

}  // namespace

double pathLength(const Trajectory& traj) {
    double len = 0;
    for (size_t i = 1; i < traj.size(); ++i)
        len += translationDistance(traj[i - 1].pose, traj[i].pose);
    return len;
}

std::string resultsMarkdown(const std::vector<RunRecord>& runs,
                            const std::vector<std::string>& sequences,
                            const std::vector<std::string>& methods, const std::string& preamble,
                            const std::vector<std::string>& plots) {
    double thr = 0.10;
    for (const auto& r : runs)
        if (r.result && r.result->map) thr = r.result->map->threshold;
    std::string md = "# SuperLoc benchmark results\n\n" + preamble + "\n";
    std::string head = "| Method |", rule = "|---|", dist = "| Distance [m] |";
    for (const auto& s : sequences) {
        head += " " + s + " |";
        rule += "---:|";
        double len = 0;
        for (const auto& r : runs)
            if (r.sequence == s) len = std::max(len, r.gt_length_m);
        dist += " " + fmt("%.0f", len) + " |";
    }
    bool any_failed = false;
    for (const Metric& m : metrics(thr)) {
        md += "\n## " + m.title + "\n\n" + head + "\n" + rule + "\n" + dist + "\n";
        // Best value per column.
        std::vector<double> best(sequences.size(), std::numeric_limits<double>::quiet_NaN());
        for (size_t c = 0; c < sequences.size() && m.better != 0; ++c)
            for (const auto& meth : methods)
                if (const RunRecord* r = find(runs, sequences[c], meth); r && r->status == "ok")
                    if (const auto v = m.get(*r); v && std::isfinite(*v))
                        if (std::isnan(best[c]) || (m.better < 0 ? *v < best[c] : *v > best[c]))
                            best[c] = *v;
        for (const auto& meth : methods) {
            md += "| " + meth + " |";
            for (size_t c = 0; c < sequences.size(); ++c) {
                const RunRecord* r = find(runs, sequences[c], meth);
                const auto v = r ? m.get(*r) : std::nullopt;
                std::string cell = "–";
                if (v && std::isfinite(*v)) {
                    cell = fmt(m.format, *v);
                    if (r->status == "ok" && fmt(m.format, *v) == fmt(m.format, best[c]))
                        cell = "**" + cell + "**";
                }
                if (r && r->status != "ok") cell += " †", any_failed = true;
                md += " " + cell + " |";
            }
            md += "\n";
        }
    }
    if (any_failed) {
        md += "\n† the run did not finish; its values (if any) cover the frames it wrote.\n\n";
        for (const auto& r : runs)
            if (r.status != "ok")
                md += "- " + r.sequence + " / " + r.method + ": " + r.status + "\n";
    }
    bool any_health = false;
    for (const auto& r : runs) any_health |= r.result && r.result->health.has_value();
    if (any_health) {
        md +=
            "\n## Health vs ground-truth error\n\nFrames per health state (doc/health.md) and error "
            "bucket: < 0.1 m | 0.1-0.5 m | > 0.5 m or > 5°. The last `ok` column must be 0: a frame "
            "that far off reported `ok` is confidently wrong.\n\n| Sequence | Method | ok | degraded | "
            "lost | ok and > 0.5 m |\n|---|---|---:|---:|---:|---:|\n";
        const auto cells = [](const std::array<size_t, 3>& c) {
            return std::to_string(c[0]) + " / " + std::to_string(c[1]) + " / " + std::to_string(c[2]);
        };
        for (const auto& r : runs) {
            if (!r.result || !r.result->health) continue;
            const auto& h = *r.result->health;
            md += "| " + r.sequence + " | " + r.method + " | " + cells(h.counts[0]) + " | " + cells(h.counts[1]) +
                  " | " + cells(h.counts[2]) + " | " + std::to_string(h.confidentlyWrong()) + " |\n";
        }
    }
    // The pose covariance's consistency (eval::consistency, doc/evaluation.md).
    bool any_cons = false;
    for (const auto& r : runs) any_cons |= r.result && r.result->consistency && r.result->consistency->frames() > 0;
    if (any_cons) {
        md +=
            "\n## Consistency of the pose covariance\n\nPer run, over its frames not lost: ANEES of the "
            "position and rotation (3 dof each: consistent at 3) and of the full pose (6 dof), and the "
            "share of frames under the chi-square 95 % bound (7.81; 12.59 for the pose; consistent at "
            "95 %) (doc/evaluation.md).\n\n| Sequence | Method | frames | ANEES pos | rot | pose | "
            "under 95 % pos | rot | pose |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
        for (const auto& r : runs) {
            if (!r.result || !r.result->consistency || r.result->consistency->frames() == 0) continue;
            const auto& c = *r.result->consistency;
            md += "| " + r.sequence + " | " + r.method + " | " + std::to_string(c.frames()) + " | " +
                  fmt("%.2f", c.anees_pos) + " | " + fmt("%.2f", c.anees_rot) + " | " +
                  (c.full ? fmt("%.2f", c.anees_pose) : std::string("–")) + " | " +
                  fmt("%.1f", 100 * c.under95_pos) + " | " + fmt("%.1f", 100 * c.under95_rot) + " | " +
                  (c.full ? fmt("%.1f", 100 * c.under95_pose) : std::string("–")) + " |\n";
        }
    }
    // Risk as a failure predictor, per method over all its sequences (eval::riskPrediction).
    std::vector<std::string> risk_methods;
    std::map<std::string, eval::RiskPrediction> risk_sum;
    for (const auto& r : runs) {
        if (!r.result || !r.result->risk) continue;
        if (!risk_sum.count(r.method)) risk_methods.push_back(r.method);
        risk_sum[r.method] += *r.result->risk;
    }
    if (!risk_methods.empty()) {
        md +=
            "\n## Risk as a failure predictor\n\nPer method, over all its sequences: for each rule "
            "(frames.csv flags_*) and axis, precision / recall of the flag for a frame whose error "
            "along that body axis exceeds [eval] risk_fail_xyz / risk_fail_deg (doc/evaluation.md). "
            "Failed frames per axis in the last row.\n";
        for (const auto& m : risk_methods) {
            const auto& p = risk_sum[m];
            md += "\n" + m + " (" + std::to_string(p.frames) + " frames):\n\n" + eval::riskPredictionMarkdown(p);
            md += "| failed frames |";
            for (int k = 0; k < 6; ++k)
                md += " " + std::to_string(p.counts[0][k].tp + p.counts[0][k].fn) + " |";
            md += "\n";
        }
    }
    // The machine of each run when they ran on several (superloc-bench --run on each).
    std::set<std::string> hosts;
    for (const auto& r : runs)
        if (!r.host.empty()) hosts.insert(r.host);
    const bool by_host = hosts.size() > 1;
    md += "\n## Runs\n\n| Sequence | Method | status | frames (est/GT) | wall [s] | peak RSS [MiB] |" +
          std::string(by_host ? " host |" : "") + "\n|---|---|---|---:|---:|---:|" +
          (by_host ? "---|" : "") + "\n";
    for (const auto& r : runs)
        md += "| " + r.sequence + " | " + r.method + " | " + r.status + " | " +
              (r.result ? std::to_string(r.result->est_frames) + "/" +
                              std::to_string(r.result->gt_frames)
                        : "–") +
              " | " + fmt("%.1f", r.wall_s) + " | " + fmt("%.0f", r.peak_rss_mb) + " |" +
              (by_host ? " " + r.host + " |" : "") + "\n";
    if (!plots.empty()) {
        md +=
            "\n## Plots\n\nTop views: GT grey, estimate coloured by min(γ_x, γ_y, γ_z) (red 0 → "
            "green 1). "
            "γ timelines: threshold dashed, frames flagged degenerate shaded. F1(τ) curves of all "
            "methods.\n\n";
        for (const auto& p : plots) md += "![" + p + "](" + p + ")\n";
    }
    return md;
}

std::string resultsJson(const std::vector<RunRecord>& runs, const std::string& suite_path,
                        std::optional<unsigned> jobs) {
    io::Json list = io::Json::array();
    for (const auto& r : runs)
        list.push_back({{"sequence", r.sequence},
                        {"method", r.method},
                        {"status", r.status},
                        {"wall_s", r.wall_s},
                        {"peak_rss_mb", r.peak_rss_mb},
                        {"gt_length_m", r.gt_length_m},
                        {"host", r.host},
                        {"version", r.version},
                        {"metrics", r.result ? eval::toJson(*r.result, false) : io::Json(nullptr)}});
    return io::toJsonText(
        {{"suite", suite_path}, {"jobs", jobs ? io::Json(*jobs) : io::Json(nullptr)}, {"runs", list}},
        "results.json");
}

std::string seedMeansMarkdown(const std::vector<RunRecord>& runs, const std::vector<SeedGroup>& groups,
                              const std::vector<std::string>& methods) {
    bool any = false;
    for (const auto& g : groups) any |= g.members.size() > 1;
    if (!any) return "";
    std::string md;
    const auto table = [&](const std::string& title, const char* f,
                           const std::function<std::optional<double>(const RunRecord&)>& get) {
        md += "\n## " + title + ", mean over seeds (min – max)\n\n| Method |";
        std::string rule = "|---|";
        for (const auto& g : groups)
            if (g.members.size() > 1) md += " " + g.name + " |", rule += "---:|";
        md += "\n" + rule + "\n";
        for (const auto& m : methods) {
            md += "| " + m + " |";
            for (const auto& g : groups) {
                if (g.members.size() <= 1) continue;
                double sum = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
                size_t n = 0;
                for (const auto& seq : g.members)
                    if (const RunRecord* r = find(runs, seq, m); r && r->status == "ok")
                        if (const auto v = get(*r); v && std::isfinite(*v))
                            sum += *v, lo = std::min(lo, *v), hi = std::max(hi, *v), ++n;
                std::string cell = "–";
                if (n > 0) {
                    cell = fmt(f, sum / double(n)) + " (" + fmt(f, lo) + " – " + fmt(f, hi) + ")";
                    if (n < g.members.size())
                        cell += " [" + std::to_string(n) + " of " + std::to_string(g.members.size()) + "]";
                }
                md += " " + cell + " |";
            }
            md += "\n";
        }
    };
    table("ATE RMSE [m]", "%.3f", [](const RunRecord& r) -> std::optional<double> {
        if (r.result && r.result->matched_frames) return r.result->ate.trans.rmse;
        return std::nullopt;
    });
    table("Map outliers [%]", "%.2f", [](const RunRecord& r) -> std::optional<double> {
        if (r.result && r.result->map) return r.result->map->outlier_percent;
        return std::nullopt;
    });
    return md;
}

}  // namespace superloc::app
