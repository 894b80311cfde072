// NearestCells: the prior map's nearest-point answers memoized on a grid (doc/map.md, "The
// association's cells").
//
// A query point's cell (edge `edge`) keeps the K map points nearest to the cell's centre, found
// once by the kd-tree when a query first reaches the cell; every later query in that cell takes
// the nearest of those K to itself: one hash probe and K distances instead of a tree descent.
// The answer is a pure function of the map and of the query (which cell, then which of its
// candidates), so it does not depend on the order of the queries, on which cells are cached or
// on the cache having been cleared. It is the kd-tree's nearest point whenever that point is
// among the cell centre's K nearest, which holds when the map is no denser than about K points
// per cell; elsewhere it is a map point at most `edge` * sqrt(3) farther than the nearest one
// (tests/map/test_nearest_cells.cpp measures how often and by how much).
#pragma once

#include <superloc/core/types.h>
#include <superloc/map/prior_map.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace superloc::map {

class NearestCells {
   public:
    static constexpr int kCandidates = 4;
    /// `edge` [m] > 0; `max_cells`: the cache is emptied when it would hold more (its answers do
    /// not change: they are recomputed on demand), so its memory stays bounded on long runs.
    explicit NearestCells(double edge, size_t max_cells = size_t(1) << 20);

    /// The memoized nearest point of `map` to x and its squared distance to x; (max uint32, +inf)
    /// when the map is empty or x is not finite or too far from the origin. Always asked with
    /// the same map (PriorMap::nearestCells keeps one per map).
    std::pair<uint32_t, float> nearest(const PriorMap& map, const Vec3f& x);

    double edge() const { return edge_; }
    size_t cells() const { return count_; }
    size_t misses() const { return misses_; }
    size_t queries() const { return queries_; }
    size_t memoryBytes() const { return slots_.capacity() * sizeof(Slot); }

   private:
    struct Candidate {
        float p[3] = {0, 0, 0};
        uint32_t index = 0;
    };
    struct Slot {
        uint64_t key = ~0ull;
        uint32_t count = 0;
        Candidate c[kCandidates];
    };
    Slot& fill(const PriorMap& map, uint64_t key, const int64_t k[3], size_t h);
    void grow();

    double edge_;
    float inv_;
    size_t max_cells_;
    std::vector<Slot> slots_;
    size_t mask_ = 0;
    size_t count_ = 0;
    size_t misses_ = 0, queries_ = 0;
    Neighbors nb_;
};

}  // namespace superloc::map
