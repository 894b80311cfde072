// PriorMap: voxel filter and registration voxel map at load; kd-tree and per-point geometry
// computed once on first use, in parallel.
#include <mrpt/system/CTicTac.h>
#include <superloc/core/voxel.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/map/prior_map.h>

#include <algorithm>
#include <limits>
#include <mutex>
#include <thread>

#include "kdtree.h"

namespace superloc::map {

struct PriorMap::Impl {
    MapParams params;
    std::vector<Vec3f> points;
    std::vector<PointGeometry> geometry;
    detail::PointsAdaptor adaptor;
    std::unique_ptr<detail::KdTree> tree;
    VoxelMap voxels;
    double prepare_seconds = 0;
    // Lazy part: kd-tree and per-point geometry, built by the first query that needs them.
    std::once_flag tree_once;
    std::vector<Vec3f> given_normals;
    std::optional<Vec3f> viewpoint;

    void buildTree();

    void computeGeometry(
        size_t begin, size_t end, const std::vector<Vec3f>& given_normals,
        const std::optional<Vec3f>& viewpoint);
};

void PriorMap::Impl::computeGeometry(
    size_t begin, size_t end, const std::vector<Vec3f>& given_normals,
    const std::optional<Vec3f>& viewpoint) {
    const size_t k = std::min<size_t>(static_cast<size_t>(params.normal_k), points.size());
    const float max_sq = static_cast<float>(params.normal_max_radius * params.normal_max_radius);
    std::vector<uint32_t> idx(k);
    std::vector<float> d2(k);
    std::vector<Vec3f> nb;
    nb.reserve(k);
    for (size_t i = begin; i < end; ++i) {
        const size_t found = tree->knnSearch(points[i].data(), k, idx.data(), d2.data());
        nb.clear();
        for (size_t j = 0; j < found; ++j)
            if (d2[j] <= max_sq) nb.push_back(points[idx[j]]);
        PointGeometry g = fitNeighborhood(nb);
        // Orientation: toward the viewpoint, else like the file's own normal, else unsigned.
        if (g.normal.squaredNorm() > 0) {
            Vec3f ref = Vec3f::Zero();
            if (viewpoint)
                ref = *viewpoint - points[i];
            else if (!given_normals.empty() && given_normals[i].allFinite())
                ref = given_normals[i];
            if (ref.squaredNorm() > 0) {
                if (g.normal.dot(ref) < 0) g.normal = -g.normal;
                g.oriented = true;
            }
        }
        geometry[i] = g;
    }
}

PriorMap::PriorMap(
    const PointCloud& cloud, const MapParams& params, const std::optional<Vec3f>& viewpoint)
    : impl_(std::make_unique<Impl>()) {
    params.validate();
    mrpt::system::CTicTac timer;
    impl_->params = params;
    // Non-finite points (only possible when the cloud did not come from io, which drops them)
    // would poison the voxel keys and the tree.
    const bool finite = std::all_of(
        cloud.points.begin(), cloud.points.end(), [](const Vec3f& p) { return p.allFinite(); });
    PointCloud filtered;
    if (finite) {
        filtered = voxelDownsample(cloud, static_cast<float>(params.voxel_size));
    } else {
        PointCloud clean = cloud;
        io::dropNonFinite(clean);
        filtered = voxelDownsample(clean, static_cast<float>(params.voxel_size));
    }
    impl_->points = std::move(filtered.points);
    impl_->given_normals = std::move(filtered.normals);
    impl_->viewpoint = viewpoint;
    impl_->voxels = VoxelMap(impl_->points, params.voxelMapParams());
    impl_->prepare_seconds = timer.Tac();
}

void PriorMap::Impl::buildTree() {
    std::call_once(tree_once, [this] {
        adaptor.pts = &points;
        tree = std::make_unique<detail::KdTree>(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
        geometry.resize(points.size());
        const size_t n = points.size();
        const size_t threads = std::max(1u, std::thread::hardware_concurrency());
        const size_t chunk = (n + threads - 1) / threads;
        std::vector<std::thread> pool;
        for (size_t t = 0; t < threads && t * chunk < n; ++t)
            pool.emplace_back([&, t] { computeGeometry(t * chunk, std::min(n, (t + 1) * chunk), given_normals, viewpoint); });
        for (auto& th : pool) th.join();
    });
}

PriorMap::~PriorMap() = default;
PriorMap::PriorMap(PriorMap&&) noexcept = default;
PriorMap& PriorMap::operator=(PriorMap&&) noexcept = default;

PriorMap PriorMap::load(const std::string& path, const MapParams& params) {
    return PriorMap(io::loadPointCloud(path), params);
}

size_t PriorMap::size() const { return impl_->points.size(); }
const std::vector<Vec3f>& PriorMap::points() const { return impl_->points; }
const Vec3f& PriorMap::point(size_t i) const { return impl_->points.at(i); }
const PointGeometry& PriorMap::geometry(size_t i) const {
    impl_->buildTree();
    return impl_->geometry.at(i);
}
const VoxelMap& PriorMap::voxels() const { return impl_->voxels; }
double PriorMap::prepareSeconds() const { return impl_->prepare_seconds; }

size_t PriorMap::memoryBytes() const {
    size_t b = impl_->points.capacity() * sizeof(Vec3f) + impl_->voxels.memoryBytes() +
               impl_->given_normals.capacity() * sizeof(Vec3f) +
               impl_->geometry.capacity() * sizeof(PointGeometry);
    if (impl_->tree) b += impl_->tree->usedMemory(*impl_->tree);
    return b;
}

void PriorMap::knn(const Vec3f& q, size_t k, Neighbors& out) const {
    impl_->buildTree();
    k = std::min(k, impl_->points.size());
    out.indices.resize(k);
    out.sq_dists.resize(k);
    if (k == 0) return;
    const size_t found = impl_->tree->knnSearch(q.data(), k, out.indices.data(), out.sq_dists.data());
    out.indices.resize(found);
    out.sq_dists.resize(found);
}

std::pair<uint32_t, float> PriorMap::nearest(const Vec3f& q) const {
    if (impl_->points.empty())
        return {std::numeric_limits<uint32_t>::max(), std::numeric_limits<float>::infinity()};
    impl_->buildTree();
    uint32_t idx = 0;
    float d2 = 0;
    impl_->tree->knnSearch(q.data(), 1, &idx, &d2);
    return {idx, d2};
}

}  // namespace superloc::map
