// Global search (issue 11, doc/relocalization.md): query time per scan and grid build time on
// the campus-ouster split map (even scans at their GT poses, 0.1 m; the odd scans queried), the
// same on kitti00-mini, and on a ~10^6-point map (the campus map tiled 2 x 2, each copy turned by
// a further 90 deg). Single thread. Data: $SUPERLOC_SHARED_DATA or ../shared/data next to the
// source tree. Run: superloc-microbench-reloc
#include <benchmark/benchmark.h>
#include <superloc/core/voxel.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>
#include <superloc/map/prior_map.h>
#include <superloc/reloc/global_search.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>

using namespace superloc;
namespace fs = std::filesystem;

namespace {

struct SplitData {
    std::vector<std::vector<Vec3f>> queries;  ///< odd scans, lidar frame
    PointCloud map_cloud;                     ///< even scans at their GT poses, voxelized
};

fs::path dataRoot() {
    const char* env = std::getenv("SUPERLOC_SHARED_DATA");
    return env ? fs::path(env) : fs::path(__FILE__).parent_path() / "../../shared/data";
}

/// Scans (sorted file names) with the GT poses in file order: even ones into the map, odd ones queried.
std::unique_ptr<SplitData> loadSplit(const fs::path& scans_dir, const fs::path& gt_tum, const std::string& ext,
                                     float voxel) {
    if (!fs::exists(gt_tum)) return nullptr;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(scans_dir))
        if (e.path().extension() == ext) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    const auto gt = io::loadTum(gt_tum.string());
    auto d = std::make_unique<SplitData>();
    PointCloud all;
    for (size_t i = 0; i < std::min(files.size(), gt.size()); ++i) {
        auto pts = io::loadPointCloud(files[i].string()).points;
        if (i % 2 == 0)
            for (const auto& p : pts) all.points.push_back((gt[i].pose * p.cast<double>()).cast<float>());
        else
            d->queries.push_back(std::move(pts));
    }
    d->map_cloud = voxelDownsample(all, voxel);
    return d;
}

const SplitData* campus() {
    static auto d = loadSplit(dataRoot() / "campus-ouster/scans", dataRoot() / "campus-ouster/gt_tum.txt", ".pcd", 0.1f);
    return d.get();
}
const SplitData* kitti() {
    static auto d = loadSplit(dataRoot() / "kitti00-mini/velodyne", dataRoot() / "kitti00-mini/gt_velodyne_tum.txt",
                              ".bin", 0.2f);
    return d.get();
}

/// The campus map tiled 2 x 2 (copy k turned by k * 90 deg about its centre), ~1.07 M points.
const PointCloud* tiled() {
    static std::unique_ptr<PointCloud> t;
    if (t || !campus()) return t.get();
    t = std::make_unique<PointCloud>();
    const auto& src = campus()->map_cloud.points;
    Eigen::AlignedBox3f box;
    for (const auto& p : src) box.extend(p);
    const Vec3f c = box.center();
    const float span = (box.max() - box.min()).head<2>().maxCoeff() + 20.f;
    for (int k = 0; k < 4; ++k) {
        const Eigen::Matrix3f R = Eigen::AngleAxisf(k * float(M_PI / 2), Vec3f::UnitZ()).toRotationMatrix();
        const Vec3f off((k % 2) * span, (k / 2) * span, 0);
        for (const auto& p : src) t->points.push_back(R * (p - c) + c + off);
    }
    return t.get();
}

map::MapParams asGiven() {
    map::MapParams mp;
    mp.voxel_size = 0;  // already voxelized
    return mp;
}

void query(benchmark::State& state, const SplitData* d, const PointCloud* cloud) {
    if (!d) {
        state.SkipWithError("shared data not found (set SUPERLOC_SHARED_DATA)");
        return;
    }
    const map::PriorMap m(*cloud, asGiven());
    const reloc::GlobalSearch gs(m, reloc::GlobalSearchParams{});
    size_t i = 0, nodes = 0;
    double best = 0;
    for (auto _ : state) {
        const auto r = gs.search(d->queries[i++ % d->queries.size()], std::nullopt);
        nodes += r.nodes;
        best += r.hypotheses.empty() ? 0.0 : r.hypotheses[0].score;
        benchmark::DoNotOptimize(r);
    }
    state.counters["map_points"] = static_cast<double>(m.size());
    state.counters["grid_MB"] = gs.memoryBytes() / 1e6;
    state.counters["build_s"] = gs.buildSeconds();
    state.counters["nodes"] = benchmark::Counter(static_cast<double>(nodes), benchmark::Counter::kAvgIterations);
    state.counters["best_score"] = benchmark::Counter(best, benchmark::Counter::kAvgIterations);
}

void build(benchmark::State& state, const PointCloud* cloud) {
    if (!cloud) {
        state.SkipWithError("shared data not found (set SUPERLOC_SHARED_DATA)");
        return;
    }
    const map::PriorMap m(*cloud, asGiven());
    size_t bytes = 0;
    for (auto _ : state) {
        const reloc::GlobalSearch gs(m, reloc::GlobalSearchParams{});
        bytes = gs.memoryBytes();
    }
    state.counters["map_points"] = static_cast<double>(m.size());
    state.counters["grid_MB"] = bytes / 1e6;
}

void BM_QueryCampus(benchmark::State& s) { query(s, campus(), campus() ? &campus()->map_cloud : nullptr); }
void BM_QueryKitti(benchmark::State& s) { query(s, kitti(), kitti() ? &kitti()->map_cloud : nullptr); }
void BM_QueryTiled1M(benchmark::State& s) { query(s, campus(), tiled()); }
void BM_BuildCampus(benchmark::State& s) { build(s, campus() ? &campus()->map_cloud : nullptr); }
void BM_BuildTiled1M(benchmark::State& s) { build(s, tiled()); }

}  // namespace

BENCHMARK(BM_QueryCampus)->Unit(benchmark::kMillisecond)->Iterations(26);
BENCHMARK(BM_QueryKitti)->Unit(benchmark::kMillisecond)->Iterations(8);
BENCHMARK(BM_QueryTiled1M)->Unit(benchmark::kMillisecond)->Iterations(26);
BENCHMARK(BM_BuildCampus)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK(BM_BuildTiled1M)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_MAIN();
