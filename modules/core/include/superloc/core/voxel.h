// Voxel-grid downsampling on a hash grid (MRPT 2.5.8 has none for point maps).
#pragma once

#include <superloc/core/types.h>

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace superloc {

/// Integer voxel key of a point for a given voxel size (64-bit: a small voxel far from the
/// origin, e.g. 1e-9 m at 10 m, needs more than 32 bits).
struct VoxelKey {
    int64_t x, y, z;
    bool operator==(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
/// A voxel's three indices packed in 63 bits, 21 each, offset by 2^20: exact for indices in
/// [-2^20, 2^20), wrapped beyond (callers keep their indices in range). Never all ones, so ~0 can
/// mark an empty slot.
inline uint64_t packVoxelIndices(int64_t x, int64_t y, int64_t z) {
    const auto q = [](int64_t v) { return static_cast<uint64_t>(v + (int64_t(1) << 20)) & 0x1FFFFFu; };
    return (q(x) << 42) | (q(y) << 21) | q(z);
}
/// Spreads a packed key over the slots of an open-addressing table (MurmurHash3's 64-bit
/// finalizer, first half).
inline uint64_t mixVoxelKey(uint64_t k) {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdULL;
    k ^= k >> 33;
    return k;
}
struct VoxelKeyHash {
    /// The three indices mixed through a 64-bit multiply-xorshift: the classic XOR of the indices
    /// times three primes sends the voxels of a corridor or a floor (small y, z ranges) into
    /// long chains of one bucket, which made the localized map's voxel set a quarter of a run.
    size_t operator()(const VoxelKey& k) const {
        uint64_t h = static_cast<uint64_t>(k.x) * 0x9E3779B97F4A7C15ULL;
        h ^= static_cast<uint64_t>(k.y) + 0x632BE59BD9B4E019ULL + (h << 6) + (h >> 2);
        h *= 0xff51afd7ed558ccdULL;
        h ^= static_cast<uint64_t>(k.z) + 0x9E3779B97F4A7C15ULL + (h << 6) + (h >> 2);
        h *= 0xc4ceb9fe1a85ec53ULL;
        return static_cast<size_t>(h ^ (h >> 33));
    }
};
/// A map from voxels (VoxelKey) to 32-bit values, flat: the three indices packed into 63 bits
/// when each is within +-2^20 (a 0.05 m voxel: +-52 km), in one open-addressing table of
/// 16-byte slots; keys beyond that in a node-based map beside it. Half the memory of a
/// std::unordered_map per entry and one cache miss per probe (the observability scan: 1.35 M
/// voxels in a 30-minute run).
class VoxelIndex {
   public:
    /// The value of k, inserting `value` first when k is new; .second: whether it was new.
    std::pair<uint32_t, bool> tryEmplace(const VoxelKey& k, uint32_t value);
    size_t size() const { return count_ + far_.size(); }
    size_t memoryBytes() const;

   private:
    struct Slot {
        uint64_t key = ~0ull;
        uint32_t value = 0;
    };
    void grow();
    std::vector<Slot> slots_ = std::vector<Slot>(64);
    size_t count_ = 0;
    std::unordered_map<VoxelKey, uint32_t, VoxelKeyHash> far_;
};

/// A set of voxels (VoxelKey), for marking the voxels a growing cloud already occupies: blocks of
/// 16 x 16 x 16 voxels, each a 512-byte bitset, found through a VoxelIndex with the last block
/// remembered. A cloud's consecutive points share blocks, so an insert is one bit test in memory
/// the last one touched, where a node-based std::unordered_set costs two or three cache misses
/// once it holds millions (the localized map of a long run).
class VoxelSet {
   public:
    /// Adds k; true when it was not in the set yet.
    bool insert(const VoxelKey& k);
    size_t size() const { return count_; }
    size_t memoryBytes() const;

   private:
    struct Block {
        uint64_t bits[64] = {};
    };
    VoxelIndex blocks_of_;       ///< block key -> index into blocks_
    std::vector<Block> blocks_;
    VoxelKey last_{0, 0, 0};
    uint32_t last_block_ = ~0u;  ///< ~0u: none yet
    size_t count_ = 0;
};

/// The first point of every voxel of a growing cloud, and each voxel's number (its first point's
/// index in points()): an open-addressing table of 4-byte point indices, a probe comparing the
/// voxel of the point a slot names (recomputed, so no key is stored). 8-16 bytes a voxel besides
/// the points (a load between a quarter and a half), against VoxelIndex's 32-64 (the
/// observability scan of a 30-minute run: 1.35 M voxels).
class VoxelFirstPoints {
   public:
    /// voxel [m] > 0 (std::invalid_argument otherwise).
    explicit VoxelFirstPoints(float voxel);
    /// p's voxel's number, appending p as its first point when the voxel is new (.second: new).
    /// Throws as voxelKey() does for a point not finite or beyond the key range.
    std::pair<uint32_t, bool> add(const Vec3f& p);
    /// The first point of each voxel, in order of first occurrence.
    const std::vector<Vec3f>& points() const { return points_; }
    size_t size() const { return points_.size(); }
    size_t memoryBytes() const;

   private:
    void grow();
    float voxel_;
    std::vector<uint32_t> slots_ = std::vector<uint32_t>(64, kEmpty);
    std::vector<Vec3f> points_;
    static constexpr uint32_t kEmpty = ~0u;
};

/// floor(p / voxel) per axis. Throws std::invalid_argument naming the voxel size and the point
/// when an index does not fit in 62 bits (a voxel far below the float resolution of the point,
/// or a non-finite point), rather than merging distant points into one voxel.
VoxelKey voxelKey(const Vec3f& p, float voxel);

/// For each occupied voxel, the index of the point kept: the one closest to the voxel's
/// centroid (so kept points are real measurements, attributes stay consistent). Indices are
/// returned in order of first occurrence, so the output is deterministic. voxel <= 0 keeps all.
std::vector<uint32_t> voxelDownsampleIndices(const std::vector<Vec3f>& points, float voxel);

/// The same, applied to every attribute of a cloud.
PointCloud voxelDownsample(const PointCloud& cloud, float voxel);

/// Selects the given indices of every attribute of a cloud.
PointCloud selectIndices(const PointCloud& cloud, const std::vector<uint32_t>& idx);

}  // namespace superloc
