#include <superloc/core/voxel.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace superloc {

bool VoxelSet::insert(const VoxelKey& k) {
    // Arithmetic shifts: floor division by 16 for negative indices too.
    const VoxelKey b{k.x >> 4, k.y >> 4, k.z >> 4};
    if (last_block_ == ~0u || !(b == last_)) {
        const auto [block, fresh] = blocks_of_.tryEmplace(b, static_cast<uint32_t>(blocks_.size()));
        if (fresh) blocks_.emplace_back();
        last_ = b;
        last_block_ = block;
    }
    const unsigned bit = static_cast<unsigned>(((k.x & 15) << 8) | ((k.y & 15) << 4) | (k.z & 15));
    uint64_t& word = blocks_[last_block_].bits[bit >> 6];
    const uint64_t m = uint64_t(1) << (bit & 63);
    if (word & m) return false;
    word |= m;
    ++count_;
    return true;
}

size_t VoxelSet::memoryBytes() const { return blocks_of_.memoryBytes() + blocks_.capacity() * sizeof(Block); }

namespace {
constexpr int64_t kPackRange = int64_t(1) << 20;
}  // namespace

std::pair<uint32_t, bool> VoxelIndex::tryEmplace(const VoxelKey& k, uint32_t value) {
    const auto fits = [](int64_t v) { return v >= -kPackRange && v < kPackRange; };
    if (!(fits(k.x) && fits(k.y) && fits(k.z))) {
        const auto [it, inserted] = far_.try_emplace(k, value);
        return {it->second, inserted};
    }
    const uint64_t key = packVoxelIndices(k.x, k.y, k.z);
    if (2 * (count_ + 1) > slots_.size()) grow();
    const size_t mask = slots_.size() - 1;
    for (size_t h = mixVoxelKey(key) & mask;; h = (h + 1) & mask) {
        Slot& s = slots_[h];
        if (s.key == key) return {s.value, false};
        if (s.key == ~0ull) {
            s.key = key;
            s.value = value;
            ++count_;
            return {value, true};
        }
    }
}

void VoxelIndex::grow() {
    std::vector<Slot> old(slots_.size() * 2);
    old.swap(slots_);
    const size_t mask = slots_.size() - 1;
    for (const Slot& s : old) {
        if (s.key == ~0ull) continue;
        for (size_t h = mixVoxelKey(s.key) & mask;; h = (h + 1) & mask)
            if (slots_[h].key == ~0ull) {
                slots_[h] = s;
                break;
            }
    }
}

size_t VoxelIndex::memoryBytes() const {
    return slots_.capacity() * sizeof(Slot) + far_.size() * (sizeof(VoxelKey) + 2 * sizeof(void*) + 8);
}

VoxelFirstPoints::VoxelFirstPoints(float voxel) : voxel_(voxel) {
    if (!(voxel > 0)) throw std::invalid_argument("VoxelFirstPoints: voxel must be > 0 m");
}

std::pair<uint32_t, bool> VoxelFirstPoints::add(const Vec3f& p) {
    const VoxelKey k = voxelKey(p, voxel_);
    if (2 * (points_.size() + 1) > slots_.size()) grow();
    const size_t mask = slots_.size() - 1;
    for (size_t h = VoxelKeyHash{}(k) & mask;; h = (h + 1) & mask) {
        uint32_t& s = slots_[h];
        if (s == kEmpty) {
            s = static_cast<uint32_t>(points_.size());
            points_.push_back(p);
            return {s, true};
        }
        if (voxelKey(points_[s], voxel_) == k) return {s, false};
    }
}

void VoxelFirstPoints::grow() {
    std::vector<uint32_t> old(slots_.size() * 2, kEmpty);
    old.swap(slots_);
    const size_t mask = slots_.size() - 1;
    for (const uint32_t s : old) {
        if (s == kEmpty) continue;
        for (size_t h = VoxelKeyHash{}(voxelKey(points_[s], voxel_)) & mask;; h = (h + 1) & mask)
            if (slots_[h] == kEmpty) {
                slots_[h] = s;
                break;
            }
    }
}

size_t VoxelFirstPoints::memoryBytes() const {
    return slots_.capacity() * sizeof(uint32_t) + points_.capacity() * sizeof(Vec3f);
}

VoxelKey voxelKey(const Vec3f& p, float voxel) {
    // The division stays in float (the keys of every voxel size that fitted 32 bits are
    // unchanged); only the range check is new.
    const float q[3] = {std::floor(p.x() / voxel), std::floor(p.y() / voxel), std::floor(p.z() / voxel)};
    constexpr float kMax = 4.6e18f;  // < 2^62
    for (const float v : q)
        if (!(std::abs(v) < kMax)) {
            std::ostringstream msg;
            msg << "voxel size " << voxel << " m is too small for the point (" << p.x() << ", " << p.y()
                << ", " << p.z() << "): its voxel index overflows (use a larger voxel, or 0 to keep every point)";
            throw std::invalid_argument(msg.str());
        }
    return {static_cast<int64_t>(q[0]), static_cast<int64_t>(q[1]), static_cast<int64_t>(q[2])};
}

std::vector<uint32_t> voxelDownsampleIndices(const std::vector<Vec3f>& points, float voxel) {
    std::vector<uint32_t> out;
    if (voxel <= 0) {
        out.resize(points.size());
        for (uint32_t i = 0; i < out.size(); ++i) out[i] = i;
        return out;
    }
    // Cells numbered by first occurrence through the flat VoxelIndex (a node-based
    // std::unordered_map here cost a global search 7 ms on a 124k-point scan, and a map's load
    // the same share); each point remembers its cell, so the second pass looks nothing up.
    VoxelIndex index;
    std::vector<uint32_t> cell_of(points.size());
    std::vector<Eigen::Vector3d> sum;
    std::vector<uint32_t> count;
    sum.reserve(points.size() / 4 + 16);
    count.reserve(points.size() / 4 + 16);
    for (uint32_t i = 0; i < points.size(); ++i) {
        const auto [c, fresh] = index.tryEmplace(voxelKey(points[i], voxel), static_cast<uint32_t>(sum.size()));
        if (fresh) sum.emplace_back(Eigen::Vector3d::Zero()), count.push_back(0);
        sum[c] += points[i].cast<double>();
        ++count[c];
        cell_of[i] = c;
    }
    // Second pass: keep per cell the point nearest the centroid (the first such, in input order).
    std::vector<Vec3f> centroid(sum.size());
    for (size_t c = 0; c < sum.size(); ++c) centroid[c] = (sum[c] / count[c]).cast<float>();
    std::vector<uint32_t> best(sum.size(), UINT32_MAX);
    std::vector<float> best_d(sum.size(), 0);
    for (uint32_t i = 0; i < points.size(); ++i) {
        const uint32_t c = cell_of[i];
        const float d = (points[i] - centroid[c]).squaredNorm();
        if (best[c] == UINT32_MAX || d < best_d[c]) {
            best[c] = i;
            best_d[c] = d;
        }
    }
    return best;
}

PointCloud selectIndices(const PointCloud& cloud, const std::vector<uint32_t>& idx) {
    PointCloud out;
    out.points.reserve(idx.size());
    for (uint32_t i : idx) out.points.push_back(cloud.points[i]);
    if (cloud.intensity.size() == cloud.size())
        for (uint32_t i : idx) out.intensity.push_back(cloud.intensity[i]);
    if (cloud.normals.size() == cloud.size())
        for (uint32_t i : idx) out.normals.push_back(cloud.normals[i]);
    if (cloud.rgb.size() == cloud.size())
        for (uint32_t i : idx) out.rgb.push_back(cloud.rgb[i]);
    return out;
}

PointCloud voxelDownsample(const PointCloud& cloud, float voxel) {
    return selectIndices(cloud, voxelDownsampleIndices(cloud.points, voxel));
}

}  // namespace superloc
