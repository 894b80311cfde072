#include <superloc/io/point_cloud_io.h>
#include <superloc/app/observability_scan.h>
#include <superloc/risk/alignment_risk.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace superloc::app {

ObservabilityScan::ObservabilityScan(double voxel) : voxel_(static_cast<float>(voxel)) {
    if (!(voxel > 0)) throw std::invalid_argument("ObservabilityScan: voxel must be > 0");
}

void ObservabilityScan::add(const std::vector<Vec3f>& points, const std::vector<int8_t>& labels) {
    const size_t n = std::min(points.size(), labels.size());
    for (size_t i = 0; i < n; ++i) {
        if (!points[i].allFinite()) continue;
        const auto [slot, inserted] =
            index_.tryEmplace(voxelKey(points[i], voxel_), static_cast<uint32_t>(points_.size()));
        if (inserted) {
            points_.push_back(points[i]);
            votes_.push_back({0, 0, 0, 0});
        }
        const int l = labels[i];
        votes_[slot][l >= 0 && l < 3 ? l : 3]++;
    }
}

PointCloud ObservabilityScan::cloud() const {
    PointCloud c;
    c.points = points_;
    c.rgb.reserve(points_.size());
    for (const auto& v : votes_) {
        const int best = static_cast<int>(std::max_element(v.begin(), v.end()) - v.begin());
        c.rgb.push_back(risk::observabilityColor(best < 3 ? best : risk::kNoLabel));
    }
    return c;
}

void ObservabilityScan::write(const std::string& path) const {
    const std::string tmp = path + ".tmp.ply";
    io::savePointCloud(tmp, cloud(), io::CloudFormat::Ply);
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec)
        throw std::runtime_error(path + ": cannot write the observability scan (" + ec.message() +
                                 ")");
}

}  // namespace superloc::app
