#include <superloc/io/point_cloud_io.h>
#include <superloc/app/observability_scan.h>
#include <superloc/risk/alignment_risk.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace superloc::app {

ObservabilityScan::ObservabilityScan(double voxel) : voxels_(static_cast<float>(voxel)) {}

void ObservabilityScan::add(const std::vector<Vec3f>& points, const std::vector<int8_t>& labels) {
    const size_t n = std::min(points.size(), labels.size());
    for (size_t i = 0; i < n; ++i) {
        if (!points[i].allFinite()) continue;
        const auto [slot, inserted] = voxels_.add(points[i]);
        if (inserted) votes_.push_back({0, 0, 0, 0});
        const int l = labels[i];
        votes_[slot][l >= 0 && l < 3 ? l : 3]++;
    }
}

std::array<uint8_t, 3> ObservabilityScan::colour(size_t i) const {
    const auto& v = votes_[i];
    const int best = static_cast<int>(std::max_element(v.begin(), v.end()) - v.begin());
    return risk::observabilityColor(best < 3 ? best : risk::kNoLabel);
}

PointCloud ObservabilityScan::cloud() const {
    PointCloud c;
    c.points = voxels_.points();
    c.rgb.reserve(c.points.size());
    for (size_t i = 0; i < votes_.size(); ++i) c.rgb.push_back(colour(i));
    return c;
}

size_t ObservabilityScan::memoryBytes() const {
    return voxels_.memoryBytes() + votes_.capacity() * sizeof(votes_[0]);
}

void ObservabilityScan::write(const std::string& path) const {
    const std::string tmp = path + ".tmp.ply";
    io::saveColouredPly(tmp, voxels_.points(), [this](size_t i) { return colour(i); });
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec)
        throw std::runtime_error(path + ": cannot write the observability scan (" + ec.message() +
                                 ")");
}

}  // namespace superloc::app
