#include <superloc/features/classify.h>
#include <superloc/localization/association.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace superloc::localization {

namespace {
void keep(const Correspondence& c, uint32_t i, std::vector<Correspondence>& out, std::vector<uint32_t>* feature_of) {
    out.push_back(c);
    if (feature_of) feature_of->push_back(i);
}

/// The correspondence of the feature p_body, at x in the map frame, with the map point j (its
/// nearest, at squared distance d2) and that point's neighbourhood geometry; false when there is
/// none. A line's direction is the principal axis of the line_knn map points nearest x, which
/// `neighbours` finds (the kd-tree, or the bounded grid).
template <class Neighbours>
bool pointCorrespondence(const Vec3d& p_body, const Vec3d& x, uint32_t j, float d2, const map::PriorMap& map,
                         const AssociationParams& p, Neighbours&& neighbours, map::Neighbors& nb,
                         Correspondence& c, AssociationStats& stats) {
    if (j == map::PointGrid::kNone || d2 > static_cast<float>(p.max_dist * p.max_dist)) {
        ++stats.too_far;
        return false;
    }
    const map::PointGeometry& g = map.geometry(j);
    c = Correspondence{};
    c.p = p_body;
    c.q = map.point(j).cast<double>();
    c.type = features::classifyShape(g.planarity, g.linearity, p.plane_max_thickness,
                                     p.line_min_linearity);
    if (c.type == FeatureType::Plane) {
        c.n = g.normal.cast<double>();
        if (c.n.squaredNorm() < 0.5) return false;
        c.weight = std::max(0.0, 1.0 - g.fit_residual / p.max_fit_residual);
        ++stats.plane;
    } else if (c.type == FeatureType::Line) {
        // Line direction: principal axis of the map neighbourhood.
        neighbours(x.cast<float>(), p.line_knn, nb);
        if (nb.indices.size() < 3) return false;
        Vec3d mean = Vec3d::Zero();
        for (uint32_t k : nb.indices) mean += map.point(k).cast<double>();
        mean /= static_cast<double>(nb.indices.size());
        Mat3d C = Mat3d::Zero();
        for (uint32_t k : nb.indices) {
            const Vec3d d = map.point(k).cast<double>() - mean;
            C += d * d.transpose();
        }
        Eigen::SelfAdjointEigenSolver<Mat3d> es;
        es.computeDirect(C);
        c.n = es.eigenvectors().col(2).normalized();
        c.q = mean;
        c.weight = g.linearity;
        ++stats.line;
    } else {
        c.weight = p.point_weight;
        ++stats.point;
    }
    return c.weight > 0;  // a weight-0 correspondence is counted by its type, not kept
}

/// The correspondence of the feature p_body, at x in the map frame, with its nearest map point
/// (kd-tree) and that point's neighbourhood geometry; false when there is none.
bool nearestCorrespondence(const Vec3d& p_body, const Vec3d& x, const map::PriorMap& map,
                           const AssociationParams& p, map::Neighbors& nb, Correspondence& c,
                           AssociationStats& stats) {
    const auto [j, d2] = map.nearest(x.cast<float>());
    const auto knn = [&map](const Vec3f& q, size_t k, map::Neighbors& out) { map.knn(q, k, out); };
    return pointCorrespondence(p_body, x, j, d2, map, p, knn, nb, c, stats);
}

void associateNearest(const std::vector<Vec3d>& pts_body, const SE3d& T_map_body,
                      const map::PriorMap& map, const AssociationParams& p,
                      std::vector<Correspondence>& out, AssociationStats& stats,
                      std::vector<uint32_t>* feature_of) {
    // Nearest map point (kd-tree) and its precomputed neighbourhood geometry.
    if (map.size() == 0) return;
    const Mat3d R = T_map_body.linear();
    const Vec3d t = T_map_body.translation();
    map::Neighbors nb;
    Correspondence c;
    for (uint32_t i = 0; i < pts_body.size(); ++i) {
        if (nearestCorrespondence(pts_body[i], R * pts_body[i] + t, map, p, nb, c, stats)) keep(c, i, out, feature_of);
    }
}

void associateVoxels(const std::vector<Vec3d>& pts_body, const SE3d& T_map_body,
                     const map::PriorMap& map, const AssociationParams& p,
                     std::vector<Correspondence>& out, AssociationStats& stats,
                     std::vector<uint32_t>* feature_of) {
    // The voxel containing the point at the level asked for (one hash probe) and its statistics.
    const map::VoxelMap& vm = map.voxels();
    if (vm.levels() == 0) return;
    const int level = std::clamp(p.level, 0, vm.levels() - 1);
    const double fit_ref = std::max(p.max_fit_residual, 0.1 * vm.levelSize(level));
    const Mat3d R = T_map_body.linear();
    const Vec3d t = T_map_body.translation();
    // At the finest level, a voxel whose plane smears the surface (a step, an edge) hands its
    // feature to the kd-tree (AssociationParams::nearest_above_thickness).
    const bool to_nearest = level == 0 && p.nearest_above_thickness > 0 && map.size() > 0;
    map::Neighbors nb;
    for (uint32_t i = 0; i < pts_body.size(); ++i) {
        const Vec3d x = R * pts_body[i] + t;
        const map::VoxelStats* v = vm.find(level, x.cast<float>());
        if (to_nearest && (!v || v->thickness > p.nearest_above_thickness)) {
            Correspondence c;
            if (nearestCorrespondence(pts_body[i], x, map, p, nb, c, stats)) keep(c, i, out, feature_of);
            continue;
        }
        if (!v) {
            ++stats.too_far;
            continue;
        }
        Correspondence c;
        c.p = pts_body[i];
        c.q = v->mean.cast<double>();
        c.type = features::classifyShape(v->planarity, v->linearity, p.plane_max_thickness,
                                         p.line_min_linearity);
        const Vec3d e = x - c.q;
        double dist = 0;
        if (c.type == FeatureType::Plane) {
            c.n = v->normal.cast<double>();
            if (c.n.squaredNorm() < 0.5) continue;
            dist = std::abs(c.n.dot(e));
            c.weight = std::max(0.0, 1.0 - v->thickness / fit_ref);
        } else if (c.type == FeatureType::Line) {
            c.n = v->direction.cast<double>();
            if (c.n.squaredNorm() < 0.5) continue;
            dist = (e - e.dot(c.n) * c.n).norm();
            c.weight = v->linearity;
        } else {
            dist = e.norm();
            c.weight = p.point_weight;
        }
        if (dist > p.max_dist) {
            ++stats.too_far;
            continue;
        }
        if (c.weight <= 0) continue;
        if (c.type == FeatureType::Plane) ++stats.plane;
        else if (c.type == FeatureType::Line) ++stats.line;
        else ++stats.point;
        keep(c, i, out, feature_of);
    }
}

/// [m] Distance from x to the nearest face of its voxel of edge `size`.
double faceDistance(const Vec3d& x, double size) {
    double d = size;
    for (int k = 0; k < 3; ++k) {
        const double f = x[k] / size - std::floor(x[k] / size);
        d = std::min(d, size * std::min(f, 1.0 - f));
    }
    return d;
}

/// planes: whether the voxel v (of edge `size`) is the feature at x's surface (AssociationParams:
/// enough points, an absolute thickness, not a line, x inside the points' footprint and near the
/// plane); then c is that point-to-plane correspondence. "Near" is also nearer than any face of
/// the voxel: a surface beyond a face (a wall whose points fall in the next voxel) is then
/// farther than this plane, so the plane is the one `nearest` would find.
bool voxelPlane(const Vec3d& p_body, const Vec3d& x, const map::VoxelStats& v, double size,
                const AssociationParams& p, Correspondence& c) {
    if (v.count < static_cast<float>(p.plane.min_points) || !(v.thickness <= p.plane.thickness) ||
        !(v.spread_minor >= p.plane.min_spread))
        return false;
    const Vec3d n = v.normal.cast<double>(), u = v.direction.cast<double>();
    const Vec3d e = x - v.mean.cast<double>();
    const double dist = std::abs(n.dot(e));
    if (!(dist <= p.plane.gate) || dist > faceDistance(x, size)) return false;
    // The footprint: within plane.footprint RMS spreads of the centroid along both in-plane axes.
    if (std::abs(u.dot(e)) > p.plane.footprint * v.spread_major ||
        std::abs(n.cross(u).dot(e)) > p.plane.footprint * v.spread_minor)
        return false;
    c = Correspondence{};
    c.p = p_body;
    c.q = v.mean.cast<double>();
    c.n = n;
    c.type = FeatureType::Plane;
    c.weight = std::max(0.0, 1.0 - v.thickness / p.max_fit_residual);
    return c.weight > 0;
}

void associatePlanes(const std::vector<Vec3d>& pts_body, const SE3d& T_map_body, const map::PriorMap& map,
                     const AssociationParams& p, std::vector<Correspondence>& out, AssociationStats& stats,
                     std::vector<uint32_t>* feature_of, std::vector<uint32_t>* hint, AssociationMemo* memo) {
    // The finest voxel's plane where it is validated (one hash probe), else the nearest map point
    // within max_dist (at most two grid cells: 27 cells, 125 when nothing is within one) and its
    // precomputed geometry: nothing unbounded.
    if (map.size() == 0) return;
    const map::VoxelMap& vm = map.voxels();
    const map::PointGrid& grid = map.grid();
    const float radius = static_cast<float>(std::min(p.max_dist, 2 * grid.cell()));
    const Mat3d R = T_map_body.linear();
    const Vec3d t = T_map_body.translation();
    const auto knn = [&grid, radius](const Vec3f& q, size_t k, map::Neighbors& nb) {
        grid.knn(q, k, radius, nb.indices, nb.sq_dists);
    };
    map::Neighbors nb;
    Correspondence c;
    if (hint && hint->size() != pts_body.size()) hint->assign(pts_body.size(), map::PointGrid::kNone);
    // The hash slots a query probes first are scattered over tables of megabytes: each query
    // asks for those of the query kAhead later, so that its own are in cache when it comes.
    // Each map position is computed once, kAhead queries early, and kept until its query.
    constexpr uint32_t kAhead = 8;
    const bool planes_first = p.voxel_planes && vm.levels() > 0;
    // The memo (AssociationMemo): a fallback answered from the last search where it cannot have
    // changed. A new memo (a new feature set or max_dist) starts empty.
    const bool recall = memo && memo->validFor(&pts_body, pts_body.size(), &map, p.max_dist);
    if (memo) {
        memo->reused = 0;
        if (!recall) {
            memo->at.resize(pts_body.size());
            memo->keep2.assign(pts_body.size(), -1.0f);
            memo->nearest.resize(pts_body.size());
            memo->max_dist = p.max_dist;
            memo->features = &pts_body;
            memo->map = &map;
        }
    }
    const auto recalled = [&](uint32_t k, const Vec3f& xk) {
        return recall && (xk - memo->at[k]).squaredNorm() < memo->keep2[k];
    };
    Vec3d ahead[kAhead];
    const auto prefetch = [&](uint32_t k) {
        if (k >= pts_body.size()) return;
        ahead[k % kAhead] = R * pts_body[k] + t;
        const Vec3f xk = ahead[k % kAhead].cast<float>();
        if (planes_first) vm.prefetch(0, xk);
        if (!recalled(k, xk)) grid.prefetch(xk);
    };
    // Float rounding of the distances compared: the gap must exceed twice the move by this much.
    constexpr float kMargin = 1e-5f;
    for (uint32_t k = 0; k < kAhead; ++k) prefetch(k);
    for (uint32_t i = 0; i < pts_body.size(); ++i) {
        const Vec3d x = ahead[i % kAhead];
        prefetch(i + kAhead);
        if (i + kAhead / 2 < pts_body.size()) {  // the cell's points, its slot now in cache
            const Vec3f xh = ahead[(i + kAhead / 2) % kAhead].cast<float>();
            if (!recalled(i + kAhead / 2, xh)) grid.prefetchPoints(xh);
        }
        const Vec3f xf = x.cast<float>();
        const map::VoxelStats* v = p.voxel_planes && vm.levels() > 0 ? vm.find(0, xf) : nullptr;
        int level = 0;
        // Where the finest voxel is too sparse for a plane (an open field's terrain, a map built
        // at 0.2 m), the twice as large voxel around it, validated the same way (the absolute
        // thickness keeps it off steps and clutter).
        if (p.voxel_planes && (!v || v->count < static_cast<float>(p.plane.min_points)) && vm.levels() > 1)
            v = vm.find(level = 1, xf);
        if (p.voxel_planes && v && voxelPlane(pts_body[i], x, *v, vm.levelSize(level), p, c)) {
            ++stats.plane;
            ++stats.voxel_planes;
            keep(c, i, out, feature_of);
            continue;
        }
        if (recalled(i, xf)) {
            // The same nearest map point, so the same plane or point correspondence.
            if (pointCorrespondence(pts_body[i], x, memo->nearest[i], 0.0f, map, p, knn, nb, c, stats))
                keep(c, i, out, feature_of);
            ++memo->reused;
            continue;
        }
        float second = 0;
        const auto [j, d2] = grid.nearest(xf, radius, hint ? (*hint)[i] : map::PointGrid::kNone, memo ? &second : nullptr);
        if (hint && j != map::PointGrid::kNone) (*hint)[i] = j;
        const size_t too_far = stats.too_far;
        if (pointCorrespondence(pts_body[i], x, j, d2, map, p, knn, nb, c, stats)) keep(c, i, out, feature_of);
        if (!memo) continue;
        // The same nearest point while q moves less than half the gap to the second nearest's
        // distance (and so still within the radius), and so the same plane or point answer. Not
        // a line (its direction is fitted to the points around q itself; c.type is the map
        // point's shape whenever one was within reach).
        const bool line = stats.too_far > too_far || c.type == FeatureType::Line;
        const float gap = j != map::PointGrid::kNone && !line ? std::sqrt(second) - std::sqrt(d2) - kMargin : -1.0f;
        memo->at[i] = xf;
        memo->nearest[i] = j;
        memo->keep2[i] = gap > 0 ? 0.25f * gap * gap : -1.0f;
    }
}

}  // namespace

AssociationParams trackingAssociation(const AssociationConfig& ac, const LocalizationParams& lp,
                                      const features::FeaturesParams& fp) {
    AssociationParams a;
    a.kind = ac.kind;
    a.max_dist = lp.max_corr_dist;
    a.nearest_above_thickness = ac.kind == AssociationKind::Voxel ? ac.voxel_nearest_above : 0.0;
    a.plane_max_thickness = fp.plane_max_thickness;
    a.line_min_linearity = fp.line_min_linearity;
    a.max_fit_residual = ac.max_fit_residual;
    a.point_weight = ac.point_weight;
    a.plane = ac.plane;
    return a;
}

void associate(const std::vector<Vec3d>& pts_body, const SE3d& T_map_body, const map::PriorMap& map,
               const AssociationParams& p, std::vector<Correspondence>& out,
               AssociationStats& stats, std::vector<uint32_t>* feature_of, std::vector<uint32_t>* nearest_hint,
               AssociationMemo* memo) {
    out.clear();
    stats = {};
    if (feature_of) feature_of->clear();
    switch (p.kind) {
        case AssociationKind::Planes:
            associatePlanes(pts_body, T_map_body, map, p, out, stats, feature_of, nearest_hint, memo);
            break;
        case AssociationKind::Voxel: associateVoxels(pts_body, T_map_body, map, p, out, stats, feature_of); break;
        case AssociationKind::Nearest: associateNearest(pts_body, T_map_body, map, p, out, stats, feature_of); break;
    }
}

InlierStats inlierStats(const std::vector<Correspondence>& corr, size_t n_features,
                        const SE3d& T_map_body, double inlier_dist) {
    InlierStats s;
    double sum2 = 0;
    for (const auto& c : corr) {
        const double e = fusion::correspondenceError(c, T_map_body);
        if (e <= inlier_dist) {
            ++s.inliers;
            sum2 += e * e;
        }
    }
    s.ratio = n_features ? static_cast<double>(s.inliers) / static_cast<double>(n_features) : 0.0;
    s.rms = s.inliers ? std::sqrt(sum2 / static_cast<double>(s.inliers)) : 0.0;
    return s;
}

}  // namespace superloc::localization
