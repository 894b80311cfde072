// Private to map: a nanoflann kd-tree over a std::vector<Vec3f>.
//
// Why nanoflann directly: it is the tree MRPT's CPointsMap uses internally (same speed, 2-4 us
// per 1-NN query on 1 M points, NOTES-platform), but CPointsMap builds its tree lazily behind a
// mutable cache, so the first concurrent queries would race; PCL's KdTreeFLANN is as fast but
// would put PCL in this module. A nanoflann index built once in the constructor has only const
// search methods with caller-owned result sets, so concurrent queries are safe.
#pragma once

#include <superloc/core/types.h>

#include <nanoflann.hpp>
#include <vector>

namespace superloc::map::detail {

struct PointsAdaptor {
    const std::vector<Vec3f>* pts = nullptr;
    size_t kdtree_get_point_count() const { return pts->size(); }
    float kdtree_get_pt(size_t idx, size_t dim) const { return (*pts)[idx][static_cast<int>(dim)]; }
    template <class BBOX>
    bool kdtree_get_bbox(BBOX&) const {
        return false;
    }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<float, PointsAdaptor, float>, PointsAdaptor, 3, uint32_t>;

}  // namespace superloc::map::detail
