// PriorMap: voxel filter and registration voxel map at load; the kd-tree built by the first
// query, each point's geometry by the first query of that point.
#include <mrpt/system/CTicTac.h>
#include <superloc/core/voxel.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/map/prior_map.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "kdtree.h"

namespace superloc::map {

struct PriorMap::Impl {
    MapParams params;
    std::vector<Vec3f> points;
    detail::PointsAdaptor adaptor;
    std::unique_ptr<detail::KdTree> tree;
    VoxelMap voxels;
    PointGrid grid;
    double prepare_seconds = 0;
    // Lazy part: the kd-tree and the geometry's storage, built by the first query that needs
    // them, and each point's geometry, computed by the first query of that point (state: 0 = not
    // yet, 1 = being computed by another thread, 2 = done).
    std::once_flag tree_once;
    std::vector<PointGeometry> geometry;
    std::unique_ptr<std::atomic<uint8_t>[]> state;
    std::vector<Vec3f> given_normals;
    std::optional<Vec3f> viewpoint;

    void buildTree();
    const PointGeometry& ensureGeometry(size_t i);
    PointGeometry computeGeometry(size_t i) const;
};

PointGeometry PriorMap::Impl::computeGeometry(size_t i) const {
    const size_t k = std::min<size_t>(static_cast<size_t>(params.normal_k), points.size());
    const float max_sq = static_cast<float>(params.normal_max_radius * params.normal_max_radius);
    uint32_t idx[200];  // normal_k <= 200 (MapParams::validate)
    float d2[200];
    const size_t found = tree->knnSearch(points[i].data(), k, idx, d2);
    std::vector<Vec3f> nb;
    nb.reserve(found);
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
    return g;
}

const PointGeometry& PriorMap::Impl::ensureGeometry(size_t i) {
    buildTree();
    std::atomic<uint8_t>& st = state[i];
    uint8_t s = st.load(std::memory_order_acquire);
    if (s == 2) return geometry[i];
    if (s == 0 && st.compare_exchange_strong(s, 1, std::memory_order_acq_rel)) {
        geometry[i] = computeGeometry(i);
        st.store(2, std::memory_order_release);
        return geometry[i];
    }
    while (st.load(std::memory_order_acquire) != 2) std::this_thread::yield();
    return geometry[i];
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
    // The points in the point grid's cell order, so that each cell's points are contiguous (the
    // grid then holds no per-point index: PointGrid).
    const std::vector<uint32_t> order = PointGrid::cellOrder(filtered.points, params.grid_cell);
    impl_->points.resize(order.size());
    for (size_t j = 0; j < order.size(); ++j) impl_->points[j] = filtered.points[order[j]];
    if (filtered.normals.size() == order.size()) {
        impl_->given_normals.resize(order.size());
        for (size_t j = 0; j < order.size(); ++j) impl_->given_normals[j] = filtered.normals[order[j]];
    }
    impl_->grid = PointGrid(impl_->points, params.grid_cell);
    impl_->viewpoint = viewpoint;
    impl_->voxels = VoxelMap(impl_->points, params.voxelMapParams());
    // After the viewpoint and the given normals: they orient each point's normal.
    if (params.geometry_at_load) prepareGeometry();
    impl_->prepare_seconds = timer.Tac();
}

void PriorMap::Impl::buildTree() {
    std::call_once(tree_once, [this] {
        adaptor.pts = &points;
        tree = std::make_unique<detail::KdTree>(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
        geometry.resize(points.size());
        state = std::make_unique<std::atomic<uint8_t>[]>(points.size());
    });
}

double PriorMap::prepareGeometry(unsigned threads) const {
    mrpt::system::CTicTac timer;
    Impl& m = *impl_;
    m.buildTree();
    const size_t n = m.points.size();
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    // Blocks of consecutive points (neighbours in the voxel filter's order share cache lines),
    // taken from a shared counter; ensureGeometry already lets two threads meet on a point.
    constexpr size_t kBlock = 4096;
    std::atomic<size_t> next{0};
    const auto work = [&m, &next, n] {
        for (size_t b = next.fetch_add(kBlock); b < n; b = next.fetch_add(kBlock))
            for (size_t i = b; i < std::min(n, b + kBlock); ++i) m.ensureGeometry(i);
    };
    std::vector<std::thread> helpers;
    const size_t extra = std::min<size_t>(threads - 1, n / kBlock);
    for (size_t t = 0; t < extra; ++t) helpers.emplace_back(work);
    work();
    for (auto& h : helpers) h.join();
    return timer.Tac();
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
    if (i >= impl_->points.size()) throw std::out_of_range("PriorMap::geometry: point index out of range");
    return impl_->ensureGeometry(i);
}
const VoxelMap& PriorMap::voxels() const { return impl_->voxels; }
const PointGrid& PriorMap::grid() const { return impl_->grid; }
double PriorMap::prepareSeconds() const { return impl_->prepare_seconds; }

size_t PriorMap::memoryBytes() const {
    size_t b = impl_->points.capacity() * sizeof(Vec3f) + impl_->voxels.memoryBytes() +
               impl_->given_normals.capacity() * sizeof(Vec3f) +
               impl_->geometry.capacity() * sizeof(PointGeometry) +
               (impl_->state ? impl_->points.size() * sizeof(std::atomic<uint8_t>) : 0) +
               impl_->grid.memoryBytes();
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
