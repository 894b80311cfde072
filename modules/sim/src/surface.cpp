#include <superloc/core/voxel.h>
#include <superloc/sim/noise.h>
#include <superloc/sim/surface.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace superloc::sim {

NearMask::NearMask(const std::vector<Vec3d>& centres, double radius) : cell_(radius / 8) {
    const int r = 9;  // cells covering radius + one cell
    std::vector<Eigen::Vector3i> seen;
    std::vector<uint64_t> centre_keys;
    for (const auto& c : centres) {
        const Eigen::Vector3i k((c / cell_).array().floor().cast<int>());
        const uint64_t key = packVoxelIndices(k.x(), k.y(), k.z());
        if (std::find(centre_keys.end() - std::min<size_t>(centre_keys.size(), 64),
                      centre_keys.end(), key) != centre_keys.end())
            continue;
        centre_keys.push_back(key);
        for (int dz = -r; dz <= r; ++dz)
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx)
                    if ((dx * dx + dy * dy + dz * dz) * cell_ * cell_ <=
                        (radius + 1.8 * cell_) * (radius + 1.8 * cell_))
                        keys_.push_back(packVoxelIndices(k.x() + dx, k.y() + dy, k.z() + dz));
        if (keys_.size() > (1u << 24)) {  // compact now and then
            std::sort(keys_.begin(), keys_.end());
            keys_.erase(std::unique(keys_.begin(), keys_.end()), keys_.end());
        }
    }
    std::sort(keys_.begin(), keys_.end());
    keys_.erase(std::unique(keys_.begin(), keys_.end()), keys_.end());
}

bool NearMask::contains(const Vec3f& p) const {
    const Eigen::Vector3i k((p.cast<double>() / cell_).array().floor().cast<int>());
    return std::binary_search(keys_.begin(), keys_.end(), packVoxelIndices(k.x(), k.y(), k.z()));
}

PointCloud sampleSurface(const Mesh& mesh, double spacing, uint64_t seed,
                         const std::function<bool(const Vec3f&)>& keep) {
    PointCloud out;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const double density = 1.0 / (spacing * spacing);
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        const Vec3d a = mesh.vertices[t[0]].cast<double>(), b = mesh.vertices[t[1]].cast<double>(),
                    c = mesh.vertices[t[2]].cast<double>();
        const double expected = mesh.area(i) * density;
        const auto n = static_cast<size_t>(expected + U(rng));
        const Vec3f normal = mesh.normal(i).cast<float>();
        for (size_t k = 0; k < n; ++k) {
            double u = U(rng), v = U(rng);
            if (u + v > 1) u = 1 - u, v = 1 - v;
            const Vec3f p = (a + (b - a) * u + (c - a) * v).cast<float>();
            if (keep && !keep(p)) continue;
            out.points.push_back(p);
            out.normals.push_back(normal);
        }
    }
    return out;
}

PointCloud makePriorMap(const PointCloud& samples, double voxel, double noise, double warp,
                        uint64_t seed) {
    // Voxelize the true surface samples first, then displace the kept points (cheaper, and the
    // displacement is what a mapping error would do to the points a user is handed).
    PointCloud kept;
    kept.points = samples.points;
    kept = voxelDownsample(kept, static_cast<float>(voxel));
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> N(0.0, 1.0);
    const FractalNoise wx(streamSeed(seed, "warp-x"), 10.0, 2),
        wy(streamSeed(seed, "warp-y"), 10.0, 2), wz(streamSeed(seed, "warp-z"), 10.0, 2);
    for (auto& p : kept.points) {
        const Vec3d q = p.cast<double>();
        const Vec3d d = warp * Vec3d(wx(q), wy(q), wz(q)) + noise * Vec3d(N(rng), N(rng), N(rng));
        p = (q + d).cast<float>();
    }
    return kept;
}

}  // namespace superloc::sim
