// Map outlier % with a nanoflann kd-tree over the GT map (libnanoflann-dev, header-only).
#include <superloc/core/voxel.h>
#include <superloc/eval/map_metrics.h>

#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>
#include <stdexcept>

namespace superloc::eval {
namespace {

/// nanoflann's dataset adaptor over a vector of points.
struct CloudAdaptor {
    const std::vector<Vec3f>& pts;
    size_t kdtree_get_point_count() const { return pts.size(); }
    float kdtree_get_pt(size_t i, size_t d) const { return pts[i][static_cast<int>(d)]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const {
        return false;
    }
};
using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, CloudAdaptor>,
                                        CloudAdaptor, 3, size_t>;

}  // namespace

MapResult computeMapOutliers(const PointCloud& est_map, const PointCloud& gt_map, double voxel,
                             double threshold) {
    if (gt_map.empty()) throw std::invalid_argument("ground-truth map has no points");
    if (est_map.empty()) throw std::invalid_argument("localized map has no points");
    const std::vector<uint32_t> keep =
        voxelDownsampleIndices(est_map.points, static_cast<float>(voxel));

    const CloudAdaptor adaptor{gt_map.points};
    KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree.buildIndex();

    MapResult r;
    r.points = keep.size();
    r.gt_points = gt_map.size();
    r.threshold = threshold;
    std::vector<double> dist(keep.size());
    size_t outliers = 0;
    double sum = 0;
    for (size_t k = 0; k < keep.size(); ++k) {
        const Vec3f& q = est_map.points[keep[k]];
        size_t idx = 0;
        float d2 = 0;
        tree.knnSearch(q.data(), 1, &idx, &d2);
        dist[k] = std::sqrt(static_cast<double>(d2));
        sum += dist[k];
        if (dist[k] > threshold) ++outliers;
    }
    r.outlier_percent = 100.0 * double(outliers) / double(keep.size());
    r.mean_dist = sum / double(keep.size());
    std::sort(dist.begin(), dist.end());
    const size_t m = dist.size() / 2;
    r.median_dist = dist.size() % 2 ? dist[m] : 0.5 * (dist[m - 1] + dist[m]);
    return r;
}

}  // namespace superloc::eval
