// MapBuilder: scans at their poses into a running-centroid voxel grid.
#include <superloc/core/se3.h>
#include <superloc/core/voxel.h>
#include <superloc/io/mrpt_maps.h>
#include <superloc/io/tum.h>
#include <mrpt/system/CTicTac.h>
#include <superloc/map/map_builder.h>
#include <superloc/map/prior_map.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace superloc::map {

namespace {

/// Sum of the points that fell in one voxel; the map point is their centroid. A centroid of
/// points on a plane lies on that plane, so walls stay sharp while noise averages out.
struct VoxelSum {
    Vec3d sum = Vec3d::Zero();
    Vec3f view = Vec3f::Zero();  ///< sum of unit vectors from the points toward their sensor
    double intensity = 0;
    uint32_t count = 0;
};

Trajectory groundTruthFromRawlog(const MapBuildOptions& o) {
    io::RawlogReader reader(o.rawlog, o.rawlog_params);
    Trajectory traj;
    io::RawlogItem item;
    while (reader.next(item))
        if (item.kind == io::RawlogItem::Kind::GroundTruth) traj.push_back(item.pose());
    if (traj.empty())
        throw std::runtime_error(
            o.rawlog + ": no '" + o.rawlog_params.gt_label +
            "' poses in the rawlog; give the scan poses with --poses TUM");
    return traj;
}

}  // namespace

MapBuilder::MapBuilder(const MapBuildOptions& options)
    : mrpt::system::COutputLogger("MapBuilder"), opts_(options) {
    if (opts_.rawlog.empty() == opts_.simplemap.empty())
        throw std::runtime_error("give one input: --rawlog FILE or --simplemap FILE");
    if (!(opts_.voxel >= 0) || !std::isfinite(opts_.voxel))
        throw std::runtime_error("--voxel must be >= 0 m");
    if (!(opts_.min_range >= 0) || !(opts_.max_range >= 0))
        throw std::runtime_error("--min-range and --max-range must be >= 0 m");
    opts_.rawlog_params.validate();
}

PointCloud MapBuilder::build(const io::ProgressFn& progress) {
    result_ = MapBuildResult{};

    const float voxel = static_cast<float>(opts_.voxel);
    const float min_r2 = static_cast<float>(opts_.min_range * opts_.min_range);
    const float max_r2 = opts_.max_range > 0
                             ? static_cast<float>(opts_.max_range * opts_.max_range)
                             : std::numeric_limits<float>::infinity();
    std::unordered_map<VoxelKey, uint32_t, VoxelKeyHash> index;
    std::vector<VoxelSum> sums;
    PointCloud all;  // voxel == 0: every point is kept
    std::vector<Vec3f> all_views;
    bool have_intensity = true;

    // One scan at its pose T = T_map_lidar into the voxel sums.
    const auto accumulate = [&](const Scan& scan, const SE3d& T) {
        const Eigen::Matrix3f R = T.linear().cast<float>();
        const Vec3d t = T.translation();
        if (scan.intensity.size() != scan.size()) have_intensity = false;
        for (size_t i = 0; i < scan.size(); ++i) {
            const Vec3f& p = scan.points[i];
            const float r2 = p.squaredNorm();
            if (r2 < min_r2 || r2 > max_r2) continue;
            const Vec3d q = (R * p).cast<double>() + t;
            const float inten = have_intensity ? scan.intensity[i] : 0.f;
            const Vec3f view = -(R * p) / std::sqrt(r2);  // toward the sensor, map axes
            ++result_.points_in;
            if (voxel <= 0) {
                all.points.push_back(q.cast<float>());
                all.intensity.push_back(inten);
                if (opts_.normals) all_views.push_back(view);
                continue;
            }
            const auto [it, fresh] =
                index.try_emplace(voxelKey(q.cast<float>(), voxel), static_cast<uint32_t>(sums.size()));
            if (fresh) sums.emplace_back();
            VoxelSum& s = sums[it->second];
            s.sum += q;
            s.intensity += inten;
            s.view += view;
            ++s.count;
        }
        ++result_.scans_used;
    };

    if (!opts_.simplemap.empty()) {
        // MRPT simplemap: each keyframe's scans at the keyframe pose (its PDF's mean).
        const auto st = io::forEachSimpleMapScan(
            opts_.simplemap, [&](const Scan& scan, const SE3d& T_map_body) {
                accumulate(scan, T_map_body * scan.T_imu_lidar);
                if (progress) progress(result_.scans_used, result_.scans_used);
            },
            opts_.rawlog_params);
        result_.poses = st.keyframes;
        if (result_.scans_used == 0)
            throw std::runtime_error(opts_.simplemap + ": no point-cloud observations in its " +
                                     std::to_string(st.keyframes) + " keyframes");
    } else {
        const Trajectory traj =
            opts_.poses_tum.empty() ? groundTruthFromRawlog(opts_) : io::loadTum(opts_.poses_tum);
        if (traj.empty()) throw std::runtime_error(opts_.poses_tum + ": no poses");
        result_.poses = traj.size();
        io::RawlogReader reader(opts_.rawlog, opts_.rawlog_params);
        io::RawlogItem item;
        size_t lidar_seen = 0;
        while (reader.next(item)) {
            if (item.kind != io::RawlogItem::Kind::Lidar) continue;
            const Scan& scan = item.scan();
            ++lidar_seen;
            const auto T_map_x = interpolateAt(traj, scan.t, opts_.max_pose_gap, 1e-4);
            if (!T_map_x) {
                if (++result_.scans_without_pose == 1)
                    MRPT_LOG_WARN_STREAM(opts_.rawlog
                                         << ": scan at t=" << scan.t
                                         << " has no pose (outside the poses' time span); "
                                            "skipped, counted");
                continue;
            }
            accumulate(scan, opts_.body_poses ? SE3d(*T_map_x * scan.T_imu_lidar) : *T_map_x);
            if (progress) progress(std::min(lidar_seen, traj.size()), traj.size());
        }
        if (lidar_seen == 0) throw std::runtime_error(reader.noScanReason());
        if (result_.scans_used == 0)
            throw std::runtime_error(
                opts_.rawlog + ": no scan could be placed (" + std::to_string(lidar_seen) +
                " LiDAR observations, none within the poses' time span)");
    }

    PointCloud map;
    std::vector<Vec3f> views;
    if (voxel <= 0) {
        map = std::move(all);
        views = std::move(all_views);
    } else {
        map.points.reserve(sums.size());
        map.intensity.reserve(sums.size());
        views.reserve(sums.size());
        for (const auto& s : sums) {
            map.points.push_back((s.sum / s.count).cast<float>());
            map.intensity.push_back(static_cast<float>(s.intensity / s.count));
            views.push_back(s.view);
        }
    }
    sums = {};
    index = {};
    if (!have_intensity) map.intensity.clear();
    if (opts_.normals) {
        mrpt::system::CTicTac timer;
        MapParams p;
        p.voxel_size = 0;
        p.normal_k = 10;
        p.normal_max_radius = std::max(0.5, 5 * opts_.voxel);
        PointCloud oriented;
        oriented.points = map.points;
        oriented.normals = std::move(views);
        // The viewing directions orient the normals (PriorMap flips each toward the given one).
        const PriorMap pm(oriented, p);
        // With voxel_size 0 the PriorMap keeps every point, in PointGrid::cellOrder: its point j
        // is the map's point order[j].
        const std::vector<uint32_t> order = PointGrid::cellOrder(map.points, p.grid_cell);
        map.normals.resize(map.size());
        for (size_t j = 0; j < pm.size(); ++j) map.normals[order[j]] = pm.geometry(j).normal;
        result_.normals_seconds = timer.Tac();
    }
    result_.map_points = map.size();
    MRPT_LOG_INFO_STREAM(
        "map: " << result_.scans_used << " scans, " << result_.points_in << " points in, "
                << result_.map_points << " map points");
    return map;
}

}  // namespace superloc::map
