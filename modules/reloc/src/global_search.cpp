// Global search: gravity-aligned branch-and-bound over the height-band pyramid, then a 6-DoF
// point-to-plane refinement per hypothesis (doc/relocalization.md).
#include <superloc/core/voxel.h>
#include <superloc/map/prior_map.h>
#include <superloc/core/se3.h>
#include <superloc/reloc/global_search.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "plane_refine.h"

namespace superloc::reloc {

namespace {


double wrapAngle(double a) {
    a = std::fmod(a + M_PI, 2 * M_PI);
    if (a < 0) a += 2 * M_PI;
    return a - M_PI;
}

/// A scan point as the search scores it: level-0 cell offset at one yaw and its band bit.
struct Offset {
    int dx, dy;
    uint32_t bit;
};

/// A branch-and-bound node: translations [ix, ix + 2^level) x [iy, iy + 2^level) at one yaw.
struct Node {
    int yaw, ix, iy, level, bound;
};

/// A leaf kept as a hypothesis.
struct Leaf {
    int yaw, ix, iy, score;
    double x, y, psi;
};

/// `n` indices spread evenly over [0, size).
std::vector<size_t> evenly(size_t size, size_t n) {
    std::vector<size_t> idx;
    if (size <= n) {
        idx.resize(size);
        for (size_t i = 0; i < size; ++i) idx[i] = i;
        return idx;
    }
    idx.reserve(n);
    const double step = static_cast<double>(size) / static_cast<double>(n);
    for (size_t i = 0; i < n; ++i) idx.push_back(static_cast<size_t>(i * step));
    return idx;
}

class BranchAndBound {
   public:
    BranchAndBound(const BandGridPyramid& grid, const std::vector<std::vector<Offset>>& offsets,
                   const std::vector<double>& yaws, const GlobalSearchParams& p, const SearchRegion* region,
                   int min_count)
        : grid_(grid), offsets_(offsets), yaws_(yaws), p_(p), region_(region), min_count_(min_count) {}

    std::vector<Leaf> run(size_t& nodes, size_t& leaves) {
        const int top = grid_.levels() - 1;
        const int S = 1 << top;
        std::vector<Node> roots;
        for (int j = 0; j < static_cast<int>(yaws_.size()); ++j)
            for (int iy = 0; iy < grid_.ny(); iy += S)
                for (int ix = 0; ix < grid_.nx(); ix += S) {
                    if (!grid_.positionValid(top, ix, iy) || !inRegion(top, ix, iy)) continue;
                    Node n{j, ix, iy, top, 0};
                    n.bound = bound(n);
                    if (n.bound >= min_count_) roots.push_back(n);
                }
        std::sort(roots.begin(), roots.end(), [](const Node& a, const Node& b) { return a.bound > b.bound; });
        for (const auto& r : roots) explore(r);
        nodes = nodes_ + roots.size();
        leaves = leaves_;
        return best_;
    }

   private:
    int threshold() const {
        return static_cast<int>(best_.size()) >= p_.max_hypotheses ? best_.back().score + 1 : min_count_;
    }

    bool inRegion(int level, int ix, int iy) const {
        if (!region_) return true;
        const double r = grid_.params().resolution;
        const int w = (1 << level) - 1;
        // Distance from the disc's centre to the rectangle of the node's cell centres.
        const double x0 = grid_.cellX(ix), x1 = grid_.cellX(ix + w), y0 = grid_.cellY(iy), y1 = grid_.cellY(iy + w);
        const double dx = std::max({x0 - region_->centre.x(), 0.0, region_->centre.x() - x1});
        const double dy = std::max({y0 - region_->centre.y(), 0.0, region_->centre.y() - y1});
        return std::hypot(dx, dy) <= region_->radius + (level == 0 ? 0.0 : 0.5 * r);
    }

    int bound(const Node& n) const {
        int hits = 0;
        for (const auto& o : offsets_[static_cast<size_t>(n.yaw)])
            if (grid_.bits(n.level, n.ix + o.dx, n.iy + o.dy) & o.bit) ++hits;
        return hits;
    }

    void explore(const Node& n) {
        if (n.bound < threshold()) return;
        if (n.level == 0) {
            ++leaves_;
            insert(n);
            return;
        }
        const int k = n.level - 1, s = 1 << k;
        Node ch[4];
        int m = 0;
        for (int c = 0; c < 4; ++c) {
            Node x{n.yaw, n.ix + (c & 1) * s, n.iy + (c >> 1) * s, k, 0};
            if (x.ix >= grid_.nx() || x.iy >= grid_.ny()) continue;
            if (!grid_.positionValid(k, x.ix, x.iy) || !inRegion(k, x.ix, x.iy)) continue;
            x.bound = bound(x);
            ++nodes_;
            ch[m++] = x;
        }
        for (int a = 1; a < m; ++a)  // best child first (insertion sort of <= 4)
            for (int b = a; b > 0 && ch[b].bound > ch[b - 1].bound; --b) std::swap(ch[b], ch[b - 1]);
        for (int c = 0; c < m; ++c) explore(ch[c]);
    }

    /// Keeps the best max_hypotheses leaves that are pairwise distinct (non-maximum suppression).
    void insert(const Node& n) {
        Leaf l{n.yaw, n.ix, n.iy, n.bound, grid_.cellX(n.ix), grid_.cellY(n.iy), yaws_[static_cast<size_t>(n.yaw)]};
        for (auto& b : best_) {
            if (std::hypot(b.x - l.x, b.y - l.y) < p_.nms_distance &&
                std::abs(wrapAngle(b.psi - l.psi)) < p_.nms_yaw_deg * kDeg) {
                if (l.score > b.score) {
                    b = l;
                    sortBest();
                }
                return;
            }
        }
        best_.push_back(l);
        sortBest();
        if (static_cast<int>(best_.size()) > p_.max_hypotheses) best_.pop_back();
    }
    void sortBest() {
        std::stable_sort(best_.begin(), best_.end(), [](const Leaf& a, const Leaf& b) { return a.score > b.score; });
    }

    const BandGridPyramid& grid_;
    const std::vector<std::vector<Offset>>& offsets_;
    const std::vector<double>& yaws_;
    const GlobalSearchParams& p_;
    const SearchRegion* region_;
    int min_count_;
    std::vector<Leaf> best_;
    size_t nodes_ = 0, leaves_ = 0;
};

}  // namespace

GlobalSearch::GlobalSearch(const map::PriorMap& map, const GlobalSearchParams& params)
    : mrpt::system::COutputLogger("GlobalSearch"), map_(map), params_(params) {
    params_.validate();
    const auto t0 = std::chrono::steady_clock::now();
    grid_ = BandGridPyramid(map.points(), params_.gridParams());
    build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MRPT_LOG_DEBUG_FMT("search grids %d x %d x %d levels, %zu occupied cells, %.1f MB, built in %.2f s", grid_.nx(),
                       grid_.ny(), grid_.levels(), grid_.occupiedCells(), grid_.memoryBytes() / 1e6, build_seconds_);
}

double GlobalSearch::scoreAt(const std::vector<Vec3f>& points_lidar, const SE3d& T) const {
    size_t hits = 0, n = 0;
    for (const auto& pf : points_lidar) {
        if (!pf.allFinite()) continue;
        ++n;
        const Vec3d q = T * pf.cast<double>();
        const uint32_t bit = grid_.bandBit(q.z() - grid_.groundAt(q.x(), q.y()));
        if (bit && (grid_.bits(0, grid_.cellIndexX(q.x()), grid_.cellIndexY(q.y())) & bit)) ++hits;
    }
    return n ? static_cast<double>(hits) / static_cast<double>(n) : 0.0;
}

GlobalSearchResult GlobalSearch::search(const std::vector<Vec3f>& points_lidar, const std::optional<Mat3d>& R_given,
                                        const SearchRegion* region) const {
    const auto t0 = std::chrono::steady_clock::now();
    const auto& p = params_;
    GlobalSearchResult res;
    const auto done = [&](const std::string& why) {
        res.failure = why;
        res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return res;
    };

    // 1. Valid points, downsampled.
    std::vector<Vec3f> valid;
    valid.reserve(points_lidar.size());
    for (const auto& q : points_lidar) {
        if (!q.allFinite()) continue;
        const float r = q.norm();
        if (r >= p.min_range && r <= p.max_range) valid.push_back(q);
    }
    res.points_in = valid.size();
    if (valid.size() < static_cast<size_t>(p.min_points)) return done("too few valid points");
    if (grid_.nx() == 0) return done("empty map");
    std::vector<Vec3f> pts;
    {
        const auto idx = voxelDownsampleIndices(valid, static_cast<float>(p.scan_voxel));
        pts.reserve(idx.size());
        for (auto i : idx) pts.push_back(valid[i]);
    }

    // 2. Gravity: the caller's roll/pitch, else the scan's ground plane, else level.
    GroundPlane gp;
    if (R_given) {
        const Mat3d R = *R_given;
        gp = estimateGroundPlane(pts, p.groundParams(), &R);
        res.gravity = GravitySource::Given;
        res.R_level_lidar = removeYaw(R);
    } else {
        gp = estimateGroundPlane(pts, p.groundParams());
        res.gravity = gp.found ? GravitySource::GroundPlane : GravitySource::AssumedLevel;
        res.R_level_lidar = gp.found ? gp.R_level_lidar : Mat3d::Identity();
    }
    res.sensor_height = gp.found ? gp.height : p.fallback_height;
    const Mat3d& R_lev = res.R_level_lidar;
    const double h = res.sensor_height;

    // 3. Scored points: above the ground clearance, inside the bands (heights from the scan's
    //    own ground plane), at most max_points spread evenly.
    std::vector<Vec3f> scored_lidar;
    std::vector<Vec3d> scored_lev;
    std::vector<uint32_t> bits;
    for (const auto& q : pts) {
        const Vec3d l = R_lev * q.cast<double>();
        const uint32_t b = grid_.bandBit(l.z() + h);
        if (!b) continue;
        scored_lidar.push_back(q);
        scored_lev.push_back(l);
        bits.push_back(b);
    }
    {
        const auto idx = evenly(scored_lidar.size(), static_cast<size_t>(p.max_points));
        std::vector<Vec3f> a;
        std::vector<Vec3d> b;
        std::vector<uint32_t> c;
        for (auto i : idx) a.push_back(scored_lidar[i]), b.push_back(scored_lev[i]), c.push_back(bits[i]);
        scored_lidar.swap(a), scored_lev.swap(b), bits.swap(c);
    }
    res.points_scored = scored_lidar.size();
    if (scored_lidar.size() < static_cast<size_t>(p.min_points)) return done("too few points above the ground");

    // 4. Yaws and each yaw's cell offsets.
    std::vector<double> yaws;
    const double step = p.yaw_step_deg * kDeg;
    if (region && region->yaw_half_width < M_PI) {
        const int n = static_cast<int>(std::floor(region->yaw_half_width / step));
        for (int j = -n; j <= n; ++j) yaws.push_back(wrapAngle(region->yaw + j * step));
    } else {
        const int n = std::max(1, static_cast<int>(std::lround(2 * M_PI / step)));
        for (int j = 0; j < n; ++j) yaws.push_back(wrapAngle(j * 2 * M_PI / n));
    }
    res.yaws = yaws.size();
    const double inv = 1.0 / p.resolution;
    std::vector<std::vector<Offset>> offsets(yaws.size());
    for (size_t j = 0; j < yaws.size(); ++j) {
        const double c = std::cos(yaws[j]), s = std::sin(yaws[j]);
        auto& o = offsets[j];
        o.reserve(scored_lev.size());
        for (size_t i = 0; i < scored_lev.size(); ++i) {
            const auto& l = scored_lev[i];
            o.push_back({static_cast<int>(std::lround((c * l.x() - s * l.y()) * inv)),
                         static_cast<int>(std::lround((s * l.x() + c * l.y()) * inv)), bits[i]});
        }
    }

    // 5. Branch-and-bound: the best max_hypotheses distinct leaves scoring >= min_score.
    const int n_scored = static_cast<int>(scored_lev.size());
    const int min_count = std::max(1, static_cast<int>(std::ceil(p.min_score * n_scored)));
    BranchAndBound bnb(grid_, offsets, yaws, p, region, min_count);
    const auto leaves = bnb.run(res.nodes, res.leaves);

    // 6. Each leaf as a 6-DoF pose (z = the map's ground + the scan's height), refined, re-scored.
    std::vector<Vec3f> refine_pts;
    for (auto i : evenly(pts.size(), 3000)) refine_pts.push_back(pts[i]);
    std::vector<PoseHypothesis> hyps;
    for (const auto& l : leaves) {
        PoseHypothesis hyp;
        SE3d T = SE3d::Identity();
        T.linear() = Eigen::AngleAxisd(l.psi, Vec3d::UnitZ()).toRotationMatrix() * R_lev;
        T.translation() = Vec3d(l.x, l.y, grid_.groundAt(l.x, l.y) + h);
        hyp.T_map_lidar_search = T;
        hyp.search_score = static_cast<double>(l.score) / n_scored;
        hyp.T_map_lidar = T;
        if (p.refine) {
            const auto r = refinePointToPlane(map_.voxels(), refine_pts, T, p.refine_iterations, p.refine_inlier_dist);
            // A refinement that runs away from its leaf (a corridor's free axis, another place)
            // is not this hypothesis any more: keep the leaf.
            const bool near = (r.T_map_lidar.translation() - T.translation()).norm() < 2.0 &&
                              Eigen::AngleAxisd(r.T_map_lidar.linear() * T.linear().transpose()).angle() < 10 * kDeg;
            // So is one that fits fewer points than the leaf did.
            if (near && r.inliers >= r.inliers_start) {
                hyp.T_map_lidar = r.T_map_lidar;
                hyp.refined = r.converged;
                hyp.fit_inliers = r.inliers;
                hyp.fit_rms = r.rms;
            } else {
                hyp.fit_inliers = r.inliers_start;
            }
        }
        hyp.score = scoreAt(scored_lidar, hyp.T_map_lidar);
        hyps.push_back(hyp);
    }
    // Best score first; equal scores (a saturated grid) by the refinement's fit.
    std::stable_sort(hyps.begin(), hyps.end(), [](const PoseHypothesis& a, const PoseHypothesis& b) {
        return a.score != b.score ? a.score > b.score : a.fit_inliers > b.fit_inliers;
    });
    // Refined hypotheses may have met: suppress again.
    for (const auto& hp : hyps) {
        bool dup = false;
        for (const auto& k : res.hypotheses)
            dup |= (hp.T_map_lidar.translation() - k.T_map_lidar.translation()).head<2>().norm() < p.nms_distance &&
                   std::abs(wrapAngle(yawOf(hp.T_map_lidar.linear()) - yawOf(k.T_map_lidar.linear()))) <
                       p.nms_yaw_deg * kDeg;
        if (!dup && hp.score >= p.min_score) res.hypotheses.push_back(hp);
    }
    if (res.hypotheses.empty()) return done("no pose scored min_score");
    for (auto& hp : res.hypotheses)
        hp.ratio_to_best = res.hypotheses[0].score > 0 ? hp.score / res.hypotheses[0].score : 0.0;
    res.runner_up_ratio = res.hypotheses.size() > 1 ? res.hypotheses[1].ratio_to_best : 0.0;
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MRPT_LOG_DEBUG_FMT("global search: %zu points, %zu yaws, %zu nodes, %zu leaves, best %.3f, runner-up %.2f, %.3f s",
                       res.points_scored, res.yaws, res.nodes, res.leaves, res.hypotheses[0].score,
                       res.runner_up_ratio, res.seconds);
    return res;
}

}  // namespace superloc::reloc
