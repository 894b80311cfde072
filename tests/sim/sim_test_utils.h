// Helpers for the sim tests: configs from the committed INIs, nearest-neighbour distances.
#pragma once

#include <superloc/app/sim_app.h>
#include <superloc/sim/sim_config.h>
#include <superloc_testing/testing.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <unordered_map>
#include <vector>

namespace simtest {
using namespace superloc;
using namespace superloc::sim;
using namespace superloc::app;

/// ini/sim/<world>.ini with overrides, plus a cheap sensor unless the test says otherwise.
inline SimConfig worldConfig(const std::string& world, std::vector<std::string> sets = {},
                             bool cheap_lidar = true) {
    if (cheap_lidar) {
        sets.insert(sets.begin(), {"lidar.beams=16", "lidar.columns=256"});
    }
    return loadSimConfig(superloc::testing::sourcePath("ini/sim/" + world + ".ini"), sets);
}

/// Distance from query points to the nearest point of a cloud (hash grid, exact within `cell`).
class NearestDistance {
 public:
    NearestDistance(const std::vector<Vec3f>& pts, double cell) : pts_(pts), cell_(cell) {
        for (uint32_t i = 0; i < pts_.size(); ++i) grid_[key(pts_[i])].push_back(i);
    }
    /// Distance to the nearest cloud point, or `cell` when none is within one cell.
    double operator()(const Vec3f& q) const {
        double best = cell_ * cell_;
        const auto k = cellOf(q);
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto it = grid_.find(pack(k[0] + dx, k[1] + dy, k[2] + dz));
                    if (it == grid_.end()) continue;
                    for (uint32_t i : it->second)
                        best = std::min<double>(best, (pts_[i] - q).squaredNorm());
                }
        return std::sqrt(best);
    }

 private:
    std::array<int64_t, 3> cellOf(const Vec3f& p) const {
        return {static_cast<int64_t>(std::floor(p.x() / cell_)),
                static_cast<int64_t>(std::floor(p.y() / cell_)),
                static_cast<int64_t>(std::floor(p.z() / cell_))};
    }
    static uint64_t pack(int64_t x, int64_t y, int64_t z) {
        return (static_cast<uint64_t>(x + (1 << 20)) << 42) ^
               (static_cast<uint64_t>(y + (1 << 20)) << 21) ^ static_cast<uint64_t>(z + (1 << 20));
    }
    uint64_t key(const Vec3f& p) const {
        const auto k = cellOf(p);
        return pack(k[0], k[1], k[2]);
    }
    const std::vector<Vec3f>& pts_;
    double cell_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> grid_;
};

inline double quantile(std::vector<double> v, double q) {
    if (v.empty()) return NAN;
    const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * v.size()));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    return v[k];
}
inline double median(std::vector<double> v) { return quantile(std::move(v), 0.5); }

inline std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace simtest
