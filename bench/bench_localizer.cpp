// Speed of the Localizer: single thread, kitti00-mini (HDL-64E, ~124k points per scan), by the
// honest protocol: prior map from the even scans at their GT poses (0.2 m voxels), the 8 odd
// scans localized. One benchmark iteration = one frame through Localizer::process (prediction,
// features, association, risk, solve), the odd scans cycled from the GT pose at the first odd
// scan, each pass in a fresh copy of the prior map (cold, as one run of superloc-localize);
// method=icp with the planes association (default: validated voxel planes, else the nearest map
// point in a bounded grid), with the kd-tree ([association] kind=nearest), with the voxel map
// (kind=voxel), with the hybrid (voxels, the kd-tree in voxels thicker than 3 cm:
// voxel_nearest_above) and method=ndt in the same run. Counter ate_m: RMSE of the frames timed (not in a map of the scans themselves). Custom counters give the median
// and p95 per frame, the median per stage and of the first frames (first_ms: wide, with the
// start check of doc/health.md) [ms]. Not a test: nothing here asserts timings.
// BM_FrameCampus*: campus-ouster the same way (map from the even scans at 0.1 m, the 26 odd
// scans 2 s apart, so every frame's velocity is unknown), with the default settings (each such
// frame measures its motion against the last scan) and with motion_from_last_scan off.
// BM_DeskewSweep: the deskew of one sweep, one constant twist vs the IMU's poses.
// BM_FrameKittiAllScans / BM_LeanIcpKittiAllScans: speed alone, all 16 kitti00-mini scans in a
// map of all of them (reference poses): the default method against a lean point-to-plane ICP
// (issue 34's yardstick), in the same run.
//   superloc-microbench-localizer [--benchmark_filter=Frame]
// Data: $SUPERLOC_SHARED_DATA or ../shared/data next to the source tree.
#include <benchmark/benchmark.h>
#include <superloc/core/se3.h>
#include <superloc/core/voxel.h>
#include <superloc/features/deskew.h>
#include <superloc/features/voxel_selector.h>
#include <superloc/imu/preintegration.h>
#include <superloc/io/point_cloud_io.h>
#include <superloc/io/tum.h>
#include <superloc/localization/localizer.h>
#include <superloc/eval/timing.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>

using namespace superloc;
using namespace superloc::localization;
namespace fs = std::filesystem;

namespace {
/// A real split: the odd scans (localized) with their GT, the prior map from the even scans.
struct SplitData {
    std::vector<Scan> scans;
    Trajectory gt;
    std::shared_ptr<map::PriorMap> map;
    bool own_scans_in_map = false;  ///< the map was built from these scans (speed only)
};

fs::path sharedData() {
    const char* env = std::getenv("SUPERLOC_SHARED_DATA");
    return env ? fs::path(env) : fs::path(__FILE__).parent_path() / "../../shared/data";
}

/// The split of one scan file per GT pose: the even scans at their GT poses make the prior map
/// (voxelized at `voxel`), the odd ones are localized.
std::unique_ptr<SplitData> splitEvenOdd(const std::vector<fs::path>& files, const Trajectory& gt, float voxel) {
    if (files.size() != gt.size() || files.empty()) return nullptr;
    auto out = std::make_unique<SplitData>();
    PointCloud all;
    for (size_t i = 0; i < files.size(); ++i) {
        Scan s;
        s.points = io::loadPointCloud(files[i].string()).points;
        s.t = gt[i].t;
        if (i % 2 == 0) {
            for (const auto& p : s.points) all.points.push_back((gt[i].pose * p.cast<double>()).cast<float>());
        } else {
            out->scans.push_back(std::move(s));
            out->gt.push_back(gt[i]);
        }
    }
    map::MapParams mp;
    mp.voxel_size = 0;  // voxelized here, as the suite's prior map
    out->map = std::make_shared<map::PriorMap>(voxelDownsample(all, voxel), mp);
    return out;
}

/// campus-ouster: scans/NNNN.pcd in name order, one gt_tum.txt line each; map at 0.1 m.
std::unique_ptr<SplitData> loadCampus() {
    const fs::path dir = sharedData() / "campus-ouster";
    if (!fs::exists(dir / "gt_tum.txt")) return nullptr;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir / "scans"))
        if (e.path().extension() == ".pcd") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return splitEvenOdd(files, io::loadTum((dir / "gt_tum.txt").string()), 0.1f);
}

const SplitData* campus() {
    static const std::unique_ptr<SplitData> d = loadCampus();
    return d.get();
}

/// kitti00-mini: velodyne/NNNNNN.bin, one gt_velodyne_tum.txt line each; map at 0.2 m, as
/// superloc-map --voxel 0.2.
std::unique_ptr<SplitData> loadKitti() {
    const fs::path dir = sharedData() / "kitti00-mini";
    if (!fs::exists(dir / "gt_velodyne_tum.txt")) return nullptr;
    const Trajectory gt = io::loadTum((dir / "gt_velodyne_tum.txt").string());
    std::vector<fs::path> files;
    for (size_t i = 0; i < gt.size(); ++i) {
        char name[64];
        std::snprintf(name, sizeof(name), "velodyne/%06zu.bin", i);
        files.push_back(dir / name);
    }
    return splitEvenOdd(files, gt, 0.2f);
}

const SplitData* kitti() {
    static const std::unique_ptr<SplitData> d = loadKitti();
    return d.get();
}

/// kitti00-mini for speed alone: the prior map from all 16 scans at the LiDAR-consistent
/// reference poses (ref_lidar_tum.txt; 0.2 m voxels), and all 16 scans localized in it. The
/// scans are in their own map, so it reports no ate_m (the split above measures accuracy).
std::unique_ptr<SplitData> loadKittiAll() {
    const fs::path dir = sharedData() / "kitti00-mini";
    if (!fs::exists(dir / "ref_lidar_tum.txt")) return nullptr;
    auto out = std::make_unique<SplitData>();
    out->gt = io::loadTum((dir / "ref_lidar_tum.txt").string());
    PointCloud all;
    for (size_t i = 0; i < out->gt.size(); ++i) {
        char name[64];
        std::snprintf(name, sizeof(name), "velodyne/%06zu.bin", i);
        Scan s;
        s.points = io::loadPointCloud((dir / name).string()).points;
        s.t = out->gt[i].t;
        for (const auto& p : s.points) all.points.push_back((out->gt[i].pose * p.cast<double>()).cast<float>());
        out->scans.push_back(std::move(s));
    }
    map::MapParams mp;
    mp.voxel_size = 0;
    out->map = std::make_shared<map::PriorMap>(voxelDownsample(all, 0.2f), mp);
    out->own_scans_in_map = true;
    return out;
}

const SplitData* kittiAll() {
    static const std::unique_ptr<SplitData> d = loadKittiAll();
    return d.get();
}

/// Settings of ini/localize-kitti.ini: the defaults and the data set's facts.
LocalizerParams kittiParams(const std::string& method) {
    LocalizerParams p;
    p.loc.method = localization::methodFromString(method);
    p.features.min_range = 2.0;
    p.features.deskew = false;
    return p;
}

/// The default INI's settings with KITTI's sensor fact (deskew off) and the voxel association.
LocalizerParams voxelParams() {
    LocalizerParams p;
    p.loc.method = localization::Method::Icp;
    p.assoc.kind = localization::AssociationKind::Voxel;
    p.loc.rounds = 10;
    p.features.deskew = false;
    return p;
}

void BM_Frame(benchmark::State& state, const LocalizerParams& params, const SplitData* d) {
    if (!d) {
        state.SkipWithError("the data set was not found (set SUPERLOC_SHARED_DATA)");
        return;
    }
    std::unique_ptr<Localizer> loc;
    size_t k = d->scans.size();
    std::vector<double> total, cpu, stage[5], first;
    double se = 0;
    for (auto _ : state) {
        if (k == d->scans.size()) {
            // Restart the sequence from the first GT pose (the first frame, with its wide
            // initial search, is timed like any other) in a fresh copy of the map: its points'
            // geometry is computed by their first query (doc/map.md), so every cycle pays what
            // one run of superloc-localize pays, not the cost of a map already warmed up.
            state.PauseTiming();
            loc.reset();
            map::MapParams mp;
            mp.voxel_size = 0;
            PointCloud cloud;
            cloud.points = d->map->points();
            loc = std::make_unique<Localizer>(params, std::make_shared<map::PriorMap>(cloud, mp));
            loc->setMinLoggingLevel(mrpt::system::LVL_ERROR);
            loc->setInitialPose(d->gt.front().pose);
            k = 0;
            state.ResumeTiming();
        }
        const FrameReport r = loc->process(d->scans[k]);
        benchmark::DoNotOptimize(r.T_map_lidar);
        se += std::pow(translationDistance(r.T_map_lidar, d->gt[k].pose), 2);
        if (k == 0) first.push_back(r.ms.total);  // wide, with the start check (doc/health.md)
        ++k;
        total.push_back(r.ms.total);
        cpu.push_back(r.ms.total_cpu);
        stage[0].push_back(r.ms.preprocess), stage[1].push_back(r.ms.associate);
        stage[2].push_back(r.ms.risk), stage[3].push_back(r.ms.solve), stage[4].push_back(r.ms.predict);
    }
    state.counters["median_ms"] = eval::median(total);
    state.counters["p95_ms"] = eval::percentile(total, 0.95);
    state.counters["median_cpu_ms"] = eval::median(cpu);
    state.counters["p95_cpu_ms"] = eval::percentile(cpu, 0.95);
    state.counters["preprocess_ms"] = eval::median(stage[0]);
    state.counters["associate_ms"] = eval::median(stage[1]);
    state.counters["risk_ms"] = eval::median(stage[2]);
    state.counters["solve_ms"] = eval::median(stage[3]);
    state.counters["predict_ms"] = eval::median(stage[4]);
    state.counters["first_ms"] = eval::median(first);
    state.counters["fps"] = 1000.0 / std::max(1e-9, eval::median(total));
    // Not for scans localized in a map built from them: an in-sample ATE says nothing.
    if (!d->own_scans_in_map) state.counters["ate_m"] = total.empty() ? 0 : std::sqrt(se / static_cast<double>(total.size()));
}

void BM_FrameIcp(benchmark::State& s) { BM_Frame(s, kittiParams("icp"), kitti()); }
void BM_FrameIcpNoStartCheck(benchmark::State& s) {
    LocalizerParams p = kittiParams("icp");
    p.relocalization.start_xyz = p.relocalization.start_deg = 0;
    BM_Frame(s, p, kitti());
}
void BM_FrameIcpVoxel(benchmark::State& s) { BM_Frame(s, voxelParams(), kitti()); }
/// `p` with the hybrid of doc/map.md: voxels, the kd-tree for features in finest voxels thicker
/// than 3 cm.
LocalizerParams hybrid(LocalizerParams p) {
    p.assoc.kind = localization::AssociationKind::Voxel;
    p.assoc.voxel_nearest_above = 0.03;
    return p;
}
/// `p` with the kd-tree association (the default before the planes association).
LocalizerParams nearest(LocalizerParams p) {
    p.assoc.kind = localization::AssociationKind::Nearest;
    return p;
}
void BM_FrameIcpNearest(benchmark::State& s) { BM_Frame(s, nearest(kittiParams("icp")), kitti()); }
void BM_FrameIcpHybrid(benchmark::State& s) { BM_Frame(s, hybrid(kittiParams("icp")), kitti()); }
void BM_FrameNdt(benchmark::State& s) { BM_Frame(s, kittiParams("ndt"), kitti()); }
/// The default settings with the data set's fact (the scans come undistorted: deskew off).
LocalizerParams campusParams(bool motion_from_last_scan) {
    LocalizerParams p;
    p.loc.method = localization::Method::Icp;
    p.loc.motion_from_last_scan = motion_from_last_scan;
    p.features.deskew = false;
    return p;
}
/// The default INI's method (superloc, no IMU, no odom_alt in these scans) with KITTI's sensor
/// facts, in the map of all scans.
void BM_FrameKittiAllScans(benchmark::State& s) { BM_Frame(s, kittiParams("superloc"), kittiAll()); }

/// The yardstick of issue 34: a lean point-to-plane ICP in the same map of all scans, nothing
/// but the registration. Each scan's points one per 0.5 m voxel (2-100 m, 2 000 taken evenly:
/// the localizer's features, by its own selector); from the last pose moved by the last motion; per iteration every
/// point's nearest map point by the kd-tree (PriorMap::nearest, within 1 m), its normal (the
/// map's PCA geometry, computed before the timing), one Gauss-Newton step of the 6 x 6 normal
/// equations; until the step is below 1 mm and 0.01 deg, at most 30 iterations. No robust
/// kernel, no prior, no risk, no health. The points' selection is timed, as the localizer's
/// preprocess is.
/// The lean ICP's registration of body points `pts` into `map` from `T`: returns the iterations.
int leanPointToPlaneIcp(const std::vector<Vec3d>& pts, const map::PriorMap& map, SE3d& T) {
    for (int it = 1; it <= 30; ++it) {
        Mat6d H = Mat6d::Zero();
        Vec6d g = Vec6d::Zero();
        for (const Vec3d& p : pts) {
            const Vec3d q = T * p;
            const auto [i, d2] = map.nearest(q.cast<float>());
            if (!(d2 <= 1.0f)) continue;
            const Vec3d n = map.geometry(i).normal.cast<double>();
            if (n.isZero()) continue;
            Vec6d J;  // of n . (q - m) under q -> Exp(dphi) q + dt: (n, q x n)
            J << n, q.cross(n);
            H += J * J.transpose();
            g += J * n.dot(q - map.point(i).cast<double>());
        }
        const Vec6d dx = H.ldlt().solve(-g);
        if (!dx.allFinite()) return it;
        T = fromVec6(dx) * T;
        if (dx.head<3>().norm() < 1e-3 && dx.tail<3>().norm() < 0.01 * kDeg) return it;
    }
    return 30;
}

void BM_LeanIcpKittiAllScans(benchmark::State& state) {
    const SplitData* d = kittiAll();
    if (!d) {
        state.SkipWithError("kitti00-mini not found");
        return;
    }
    d->map->prepareGeometry(1);
    std::vector<Vec3d> pts;
    features::VoxelSelector selector;  // the localizer's own (its preprocess): no handicap
    std::vector<uint32_t> valid, candidates, chosen;
    size_t k = d->scans.size();
    SE3d T = SE3d::Identity(), T_prev = SE3d::Identity();
    std::vector<double> ms, iters;
    for (auto _ : state) {
        if (k == d->scans.size()) k = 0, T = T_prev = d->gt.front().pose;
        const auto t0 = std::chrono::steady_clock::now();
        selector.selectInRange(d->scans[k].points, 2.0f, 100.0f, 0.5f, valid, candidates);
        features::takeEvenly(candidates, 2000, chosen);
        pts.clear();
        for (uint32_t i : chosen) pts.push_back(d->scans[k].points[i].cast<double>());
        const SE3d motion = T_prev.inverse() * T;  // constant velocity
        T_prev = T;
        T = T * motion;
        iters.push_back(leanPointToPlaneIcp(pts, *d->map, T));
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        benchmark::DoNotOptimize(T);
        ++k;
    }
    state.counters["median_ms"] = eval::median(ms);
    state.counters["iterations"] = eval::median(iters);
}

void BM_FrameCampus(benchmark::State& s) { BM_Frame(s, campusParams(true), campus()); }
void BM_FrameCampusVelocityAssumed(benchmark::State& s) { BM_Frame(s, campusParams(false), campus()); }
void BM_FrameCampusHybrid(benchmark::State& s) { BM_Frame(s, hybrid(campusParams(true)), campus()); }
void BM_FrameCampusNearest(benchmark::State& s) { BM_Frame(s, nearest(campusParams(true)), campus()); }

/// One recovered frame (no IMU; the relocalization of doc/health.md): scans 0 and 1 tracked, then
/// scan 2 with its points turned by 45 deg about the sensor's z axis, as if the car had turned
/// 45 deg more than the constant-velocity prediction says. Only that frame is timed; the
/// `recovered` counter is the share of iterations in which the local search found a pose, the
/// worst_err_* counters how far that pose is from the truth.
void BM_RecoveryFrame(benchmark::State& state) {
    const SplitData* d = kitti();
    if (!d) {
        state.SkipWithError("kitti00-mini not found");
        return;
    }
    const LocalizerParams params = kittiParams("icp");
    Scan turned = d->scans[2];
    const Eigen::Matrix3f Rz = Eigen::AngleAxisf(static_cast<float>(M_PI / 4), Eigen::Vector3f::UnitZ()).toRotationMatrix();
    for (auto& p : turned.points) p = Rz * p;
    double recovered = 0, n = 0, err_m = 0, err_deg = 0;
    std::vector<double> total;
    for (auto _ : state) {
        state.PauseTiming();
        Localizer loc(params, d->map);
        loc.setMinLoggingLevel(mrpt::system::LVL_ERROR);
        loc.setInitialPose(d->gt.front().pose);
        loc.process(d->scans[0]);
        loc.process(d->scans[1]);
        state.ResumeTiming();
        const FrameReport r = loc.process(turned);
        benchmark::DoNotOptimize(r.T_map_lidar);
        recovered += r.recovered;
        n += 1;
        // The turned scan's true pose: T_gt2 * Rz^T (its points are Rz times the original).
        SE3d T_true = d->gt[2].pose;
        T_true.linear() = T_true.linear() * Rz.cast<double>().transpose();
        err_m = std::max(err_m, translationDistance(T_true, r.T_map_lidar));
        err_deg = std::max(err_deg, rotationAngle(T_true, r.T_map_lidar) * 180 / M_PI);
        total.push_back(r.ms.total);
    }
    state.counters["recovered"] = n > 0 ? recovered / n : 0;
    state.counters["worst_err_m"] = err_m;
    state.counters["worst_err_deg"] = err_deg;
    state.counters["median_ms"] = eval::median(total);
}

/// The association step alone: 2000 features of scan 5 at its GT pose; Arg(0) nearest (kd-tree),
/// Arg(1) planes (the default), Arg(2) planes without voxel planes (every feature on the bounded
/// grid fallback: a frame weak in translation, [association] points_below_gamma) on a solve's
/// first round, Arg(3) the same on a later round (each feature's last match as the search's hint),
/// Arg(4) the first round as a solve makes it (recording the memo: the search also bounds the
/// second nearest), Arg(5) a later round as a solve makes it (hint and memo of a round 3 mm and
/// 0.01 deg away: a settled frame's step; only the features the memo cannot answer searched).
void BM_Association(benchmark::State& state) {
    const SplitData* d = kitti();
    if (!d) {
        state.SkipWithError("kitti00-mini not found");
        return;
    }
    std::vector<Vec3d> pts;
    const auto& scan = d->scans[5];
    for (uint32_t i : voxelDownsampleIndices(scan.points, 0.5f))
        if (pts.size() < 2000 && scan.points[i].norm() > 2 && scan.points[i].norm() < 60)
            pts.push_back(scan.points[i].cast<double>());
    // The thresholds this benchmark has always timed (AssociationParams' defaults until they were
    // made the run's: plane_max_thickness 0.5, point_weight 0), kept so that its figures stay
    // comparable with earlier runs.
    AssociationParams ap;
    ap.plane_max_thickness = 0.1;
    ap.point_weight = 0.1;
    ap.kind = state.range(0) >= 1 ? localization::AssociationKind::Planes : localization::AssociationKind::Nearest;
    ap.voxel_planes = state.range(0) <= 1;
    const bool hinted = state.range(0) == 3 || state.range(0) == 5;
    const bool memo = state.range(0) >= 4;
    d->map->grid();  // built at load by the run (geometry_at_load)
    std::vector<Correspondence> corr;
    AssociationStats st;
    std::vector<uint32_t> hint, hint0;
    localization::AssociationMemo last, m;
    SE3d T = d->gt[5].pose;
    if (hinted) associate(pts, T, *d->map, ap, corr, st, nullptr, &hint0, memo ? &last : nullptr);
    if (state.range(0) == 5) {
        SE3d step = SE3d::Identity();
        step.linear() = Eigen::AngleAxisd(0.01 * M_PI / 180, Vec3d(0.3, 0.2, 0.93).normalized()).toRotationMatrix();
        step.translation() = Vec3d(0.002, -0.002, 0.001);
        T = T * step;
    }
    size_t reused = 0;
    for (auto _ : state) {
        state.PauseTiming();
        hint = hint0;
        if (memo) m = last;
        state.ResumeTiming();
        associate(pts, T, *d->map, ap, corr, st, nullptr, ap.voxel_planes ? nullptr : &hint, memo ? &m : nullptr);
        benchmark::DoNotOptimize(corr.data());
        reused = m.reused;
    }
    state.counters["reused"] = static_cast<double>(reused);
    state.counters["features"] = static_cast<double>(pts.size());
    state.counters["too_far"] = static_cast<double>(st.too_far);
    state.counters["voxel_planes"] = static_cast<double>(st.voxel_planes);
    state.counters["map_points"] = static_cast<double>(d->map->size());
    state.counters["per_query_us"] =
        benchmark::Counter(static_cast<double>(pts.size()), benchmark::Counter::kIsIterationInvariantRate |
                                                                benchmark::Counter::kInvert);
}
/// Step 2's selection alone (VoxelSelector::selectInRange, as Preprocessor::run calls it): the
/// range filter and the first point of every 0.5 m voxel of KITTI scan 5 (124k points).
void BM_ScanSelection(benchmark::State& state) {
    const SplitData* d = kitti();
    if (!d) {
        state.SkipWithError("kitti00-mini not found");
        return;
    }
    const auto& points = d->scans[5].points;
    features::VoxelSelector sel;
    std::vector<uint32_t> valid, out;
    for (auto _ : state) {
        sel.selectInRange(points, 2.0f, 100.0f, 0.5f, valid, out);
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["points"] = static_cast<double>(points.size());
    state.counters["candidates"] = static_cast<double>(out.size());
    state.counters["per_point_ns"] = benchmark::Counter(
        static_cast<double>(points.size()) * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ScanSelection)->Unit(benchmark::kMicrosecond);

/// Deskew of one sweep's 2000 features (doc/localizer.md step 2): Arg(0) one constant twist
/// (SweepMotion::fromTwist), Arg(1) along the IMU's trajectory (imu::sweepPoses: the poses
/// predicted from the previous state at 17 times over the 0.1 s sweep, 200 Hz samples, then
/// SweepMotion::fromSamples), the default with IMU, as Localizer::preprocess does it. Both include deskewing the 2000 points.
void BM_DeskewSweep(benchmark::State& state) {
    std::vector<Vec3f> points(2000);
    std::vector<float> rel(points.size());
    std::vector<uint32_t> idx(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const double a = 0.01 * static_cast<double>(i);
        points[i] = Vec3f(static_cast<float>(10 * std::cos(a)), static_cast<float>(10 * std::sin(a)), 1.0f);
        rel[i] = -0.1f + 0.1f * static_cast<float>(i) / static_cast<float>(points.size());
        idx[i] = static_cast<uint32_t>(i);
    }
    std::vector<ImuSample> imu;
    for (int k = 0; k <= 44; ++k) {  // 0.22 s at 200 Hz around the sweep
        ImuSample s;
        s.t = 0.9 + 0.005 * k;
        s.acc = Vec3d(0.5, 0.1 * std::sin(0.3 * k), 9.81 + std::sin(k));
        s.gyro = Vec3d(0.01, -0.02, 0.5);
        imu.push_back(s);
    }
    imu::NavState prev;
    prev.v = Vec3d(5, 0, 0);
    const double t = 1.1, s_min = -0.1;
    std::vector<Vec3f> out;
    for (auto _ : state) {
        features::SweepMotion motion;
        if (state.range(0) == 0) {
            motion = features::SweepMotion::fromTwist(Vec3d(5, 0, 0), Vec3d(0.01, -0.02, 0.5), -s_min);
        } else {
            const auto sp = imu::sweepPoses(imu, 1.0, prev, imu::ImuBias{}, Vec3d(0, 0, -9.81), t, s_min,
                                            SE3d::Identity());
            motion = features::SweepMotion::fromSamples(sp.s, sp.T_end_s);
        }
        features::deskewPoints(points, rel, idx, motion, out);
        benchmark::DoNotOptimize(out.data());
    }
}
}  // namespace

BENCHMARK(BM_DeskewSweep)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FrameIcp)->Unit(benchmark::kMillisecond)->Iterations(160);
BENCHMARK(BM_FrameIcpNoStartCheck)->Unit(benchmark::kMillisecond)->Iterations(160);
BENCHMARK(BM_FrameIcpVoxel)->Unit(benchmark::kMillisecond)->Iterations(160);
BENCHMARK(BM_FrameIcpHybrid)->Unit(benchmark::kMillisecond)->Iterations(160);
BENCHMARK(BM_FrameIcpNearest)->Unit(benchmark::kMillisecond)->Iterations(160);
BENCHMARK(BM_FrameNdt)->Unit(benchmark::kMillisecond)->Iterations(48);
BENCHMARK(BM_FrameKittiAllScans)->Unit(benchmark::kMillisecond)->Iterations(160);
BENCHMARK(BM_LeanIcpKittiAllScans)->Unit(benchmark::kMillisecond)->Iterations(160);
BENCHMARK(BM_FrameCampus)->Unit(benchmark::kMillisecond)->Iterations(52);
BENCHMARK(BM_FrameCampusVelocityAssumed)->Unit(benchmark::kMillisecond)->Iterations(52);
BENCHMARK(BM_FrameCampusHybrid)->Unit(benchmark::kMillisecond)->Iterations(52);
BENCHMARK(BM_FrameCampusNearest)->Unit(benchmark::kMillisecond)->Iterations(52);
BENCHMARK(BM_Association)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Arg(4)->Arg(5)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RecoveryFrame)->Unit(benchmark::kMillisecond)->Iterations(5);

BENCHMARK_MAIN();
