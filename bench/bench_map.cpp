// PriorMap preparation on a 1 M-point map and kd-tree query cost (issue 2: "loading + preparing
// a 1 M-point map takes seconds"), and the scaling of both associations (the registration voxel
// map and the default nearest-point one): preparation time, resident bytes per map point and
// association cost for the same hall sampled with 1e5, 1e6 and 1e7 points (doc/map.md).
// Run: superloc-microbench-map
#include <benchmark/benchmark.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/localization/association.h>
#include <superloc/localization/localizer.h>
#include <superloc/io/map_tiles.h>
#include <superloc/map/prior_map.h>
#include <superloc/map/tiled_map.h>

#include <chrono>

#include <cmath>
#include <filesystem>
#include <random>

using namespace superloc;

namespace {

/// ~1 M points on the walls, floor and ceiling of a 50 m x 20 m x 4 m hall, 1 cm noise.
PointCloud hall(size_t n) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    std::normal_distribution<float> noise(0.f, 0.01f);
    PointCloud c;
    c.points.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        const float a = U(rng), b = U(rng);
        switch (i % 4) {
            case 0: c.points.emplace_back(50 * a, 20 * b, noise(rng)); break;       // floor
            case 1: c.points.emplace_back(50 * a, 20 * b, 4 + noise(rng)); break;   // ceiling
            case 2: c.points.emplace_back(50 * a, noise(rng), 4 * b); break;        // wall
            default: c.points.emplace_back(noise(rng), 20 * a, 4 * b); break;       // wall
        }
    }
    return c;
}

/// 2000 association features on the hall's surfaces (2 cm off), shifted by `offset`.
std::vector<Vec3d> hallFeatures(const Vec3f& offset = Vec3f::Zero()) {
    std::vector<Vec3d> feats;
    for (const Vec3f& q : hall(2000).points) feats.push_back((q + offset + Vec3f(0.02f, 0.02f, 0.02f)).cast<double>());
    return feats;
}

/// Median [ms] of 200 associations of `feats` at the identity (after one untimed), and the
/// correspondences of the last one.
double medianAssociationMs(const std::vector<Vec3d>& feats, const map::PriorMap& m,
                           const localization::AssociationParams& ap, size_t* matched = nullptr) {
    std::vector<Correspondence> corr;
    localization::AssociationStats st;
    localization::associate(feats, SE3d::Identity(), m, ap, corr, st);
    std::vector<double> ms;
    for (int k = 0; k < 200; ++k) {
        const auto a = std::chrono::steady_clock::now();
        localization::associate(feats, SE3d::Identity(), m, ap, corr, st);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a).count());
    }
    std::nth_element(ms.begin(), ms.begin() + 100, ms.end());
    if (matched) *matched = corr.size();
    return ms[100];
}

void BM_PrepareMap1M(benchmark::State& state) {
    const PointCloud cloud = hall(1'000'000);
    map::MapParams p;
    p.voxel_size = 0;  // keep all 1 M points
    for (auto _ : state) {
        const map::PriorMap m(cloud, p);
        benchmark::DoNotOptimize(m.size());
        state.counters["points"] = static_cast<double>(m.size());
    }
}
BENCHMARK(BM_PrepareMap1M)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_LoadPcdAndPrepare1M(benchmark::State& state) {
    const auto path = std::filesystem::temp_directory_path() / "superloc_bench_map_1m.pcd";
    io::savePointCloud(path.string(), hall(1'000'000));
    map::MapParams p;
    p.voxel_size = 0.05;
    for (auto _ : state) {
        const auto m = map::PriorMap::load(path.string(), p);
        benchmark::DoNotOptimize(m.size());
        state.counters["points"] = static_cast<double>(m.size());
    }
    std::filesystem::remove(path);
}
BENCHMARK(BM_LoadPcdAndPrepare1M)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_Knn10(benchmark::State& state) {
    map::MapParams p;
    p.voxel_size = 0;
    const map::PriorMap m(hall(1'000'000), p);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    map::Neighbors nb;
    for (auto _ : state) {
        m.knn(Vec3f(50 * U(rng), 20 * U(rng), 4 * U(rng)), 10, nb);
        benchmark::DoNotOptimize(nb.indices.data());
    }
}
BENCHMARK(BM_Knn10)->Unit(benchmark::kMicrosecond);

/// The same hall with state.range(0) points, for each association (state.range(1): 0 = nearest,
/// kd-tree and per-point geometry on first use; 1 = voxel, the registration voxel map; 2 =
/// planes, the default: validated voxel planes, else the point grid and per-point geometry). Counters: prepare_s_per_1M (PriorMap, plus for nearest the kd-tree the first query
/// builds), bytes_per_point (after the associations: points, voxel map, and for nearest the
/// kd-tree and the geometry), first_assoc_ms (the first association: for nearest it computes the
/// geometry of the points it touches), assoc_ms_2000 (median of 200 later associations of 2000
/// features near the surfaces), matched, voxels_finest.
void BM_MapScale(benchmark::State& state) {
    const size_t n = static_cast<size_t>(state.range(0));
    const bool voxel = state.range(1) == 1;
    const bool planes = state.range(1) == 2;
    const PointCloud cloud = hall(n);
    map::MapParams p;
    p.voxel_size = 0;
    const std::vector<Vec3d> feats = hallFeatures();
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const map::PriorMap m(cloud, p);
        if (!voxel) m.nearest(Vec3f::Zero());  // builds the kd-tree
        if (planes) m.grid();                    // builds the point grid
        const double prep = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        localization::AssociationParams ap;  // the thresholds timed before the defaults became the run's
        ap.plane_max_thickness = 0.1;
        ap.point_weight = 0.1;
        ap.kind = voxel ? localization::AssociationKind::Voxel
                        : (planes ? localization::AssociationKind::Planes : localization::AssociationKind::Nearest);
        std::vector<Correspondence> corr;
        localization::AssociationStats st;
        const auto f0 = std::chrono::steady_clock::now();
        localization::associate(feats, SE3d::Identity(), m, ap, corr, st);
        state.counters["first_assoc_ms"] =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - f0).count();
        size_t matched = 0;
        state.counters["assoc_ms_2000"] = medianAssociationMs(feats, m, ap, &matched);
        state.counters["prepare_s_per_1M"] = prep / (static_cast<double>(n) / 1e6);
        state.counters["bytes_per_point"] = static_cast<double>(m.memoryBytes()) / static_cast<double>(n);
        state.counters["voxels_finest"] = static_cast<double>(m.voxels().info()[0].voxels);
        state.counters["matched"] = static_cast<double>(matched);
    }
}
BENCHMARK(BM_MapScale)
    ->ArgsProduct({{100'000, 1'000'000, 10'000'000}, {0, 1, 2}})
    ->ArgNames({"points", "voxel"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

/// A 10^7-point "city" on disk in tiles, localized in through the tiles around the robot
/// (doc/map.md "Tiled maps"): 100 halls of 10^5 points (50 x 20 x 4 m each, on a 10 x 10 grid
/// 60 m x 30 m apart: 600 m x 300 m) written as 50 m tiles, then the tiles within 100 m of the
/// middle hall loaded as the Localizer's map. Counters: write_s (splitting and writing all
/// tiles), load_s (reading + preparing the tiles around), points_loaded of points_total,
/// resident_MB of the loaded map after the associations (kd-tree and touched geometry
/// included), assoc_ms_2000 (median of 200 associations of 2000 features in the middle hall)
/// and assoc_ms_2000_one_hall (the same features in a map of that hall alone); localizer_prepare_s
/// and search_MB: Localizer::prepareMap on the loaded map with the default parameters (the
/// global search's grids), as the app does in its thread at each reload.
void BM_TiledCity10M(benchmark::State& state) {
    const PointCloud one = hall(100'000);
    PointCloud city;
    city.points.reserve(100 * one.size());
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j)
            for (const Vec3f& p : one.points) city.points.push_back(p + Vec3f(60.f * i, 30.f * j, 0.f));
    const auto dir = std::filesystem::temp_directory_path() / "superloc_bench_tiled_city";
    std::filesystem::remove_all(dir);
    const Vec3f mid(60.f * 5, 30.f * 5, 0.f);
    const std::vector<Vec3d> feats = hallFeatures(mid);
    map::MapParams p;
    p.voxel_size = 0;
    localization::AssociationParams ap;  // the thresholds timed before the defaults became the run's
    ap.plane_max_thickness = 0.1;
    ap.point_weight = 0.1;
    ap.kind = localization::AssociationKind::Nearest;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const io::MapTileIndex index = io::writeMapTiles(city, 50.0, dir.string());
        const double write_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        map::TiledMap tiles(dir.string(), p, 100.0);
        const auto around = tiles.loadAround(mid.cast<double>());
        around->nearest(Vec3f::Zero());  // the kd-tree, as the first frame builds it
        const double load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() - write_s;
        state.counters["write_s"] = write_s;
        state.counters["load_s"] = load_s;
        state.counters["points_total"] = static_cast<double>(index.totalPoints());
        state.counters["points_loaded"] = static_cast<double>(around->size());
        state.counters["assoc_ms_2000"] = medianAssociationMs(feats, *around, ap);
        state.counters["resident_MB"] = static_cast<double>(around->memoryBytes()) / 1e6;
        // What the Localizer builds on it with the default parameters (the global search).
        const auto p0 = std::chrono::steady_clock::now();
        const localization::PreparedMap prepared = localization::Localizer::prepareMap(localization::LocalizerParams{}, around);
        state.counters["localizer_prepare_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - p0).count();
        state.counters["search_MB"] = prepared.search ? static_cast<double>(prepared.search->memoryBytes()) / 1e6 : 0.0;
        PointCloud alone;
        for (const Vec3f& q : one.points) alone.points.push_back(q + mid);
        state.counters["assoc_ms_2000_one_hall"] = medianAssociationMs(feats, map::PriorMap(alone, p), ap);
    }
    std::filesystem::remove_all(dir);
}
BENCHMARK(BM_TiledCity10M)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
