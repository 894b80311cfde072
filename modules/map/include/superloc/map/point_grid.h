// A fine hash grid over the map points: bounded nearest-neighbour queries for the association's
// fallback (doc/map.md, "The planes association").
//
// Cells of edge `cell`; each cell's points are stored contiguously (the points sorted by cell),
// found by one hash probe. A query of radius r <= cell visits the cell containing it, then those
// of its 26 neighbours whose box is nearer than the best point found so far; a radius up to
// 2 cell also the 98 cells around those, again only where a box is nearer than the best point
// (so only when nothing was found within about a cell). The exact nearest point within r, and
// never more than 27 (r <= cell) or 125 cells, whatever the map's size. The
// points themselves are the caller's, read in place: given in cell order (cellOrder(), as
// PriorMap keeps its points) a cell's points are contiguous in memory and the grid holds 16 bytes
// per occupied cell only; in any other order it also keeps their indices in cell order (4 bytes
// per point).
#pragma once

#include <superloc/core/types.h>

#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace superloc::map {

class PointGrid {
   public:
    static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

    PointGrid() = default;
    /// A grid over `points`, which must outlive it unchanged (they are read in place). Throws
    /// std::invalid_argument when `cell` is not > 0.
    PointGrid(const std::vector<Vec3f>& points, double cell);

    /// The permutation that sorts `points` by cell of edge `cell` (within a cell, by index; points
    /// outside the grid's range or not finite last).
    static std::vector<uint32_t> cellOrder(const std::vector<Vec3f>& points, double cell);

    double cell() const { return cell_; }
    /// The nearest point to q within max_dist (clamped to 2 cell()): its index in the points
    /// given to the constructor and its squared distance; {kNone, inf} when there is none.
    /// `hint` (kNone: none): any point's index, e.g. the last answer for a query nearby; the
    /// search starts from its distance, so only cells nearer than it are visited. The answer is
    /// the same. `second` (if not null) receives a lower bound on the squared distance from q of
    /// every other point within the radius: the nearest of the other points the search measured,
    /// the cells it left unvisited, and the radius. q may move by less than half the gap between
    /// the two distances and keep the same answer. It costs the search nothing.
    std::pair<uint32_t, float> nearest(const Vec3f& q, float max_dist, uint32_t hint = kNone,
                                       float* second = nullptr) const;
    /// Asks the CPU to fetch the hash slot of q's cell (a query a few ahead of the current one:
    /// its probe then finds the slot in cache). No effect on any answer.
    void prefetch(const Vec3f& q) const;
    /// Asks the CPU to fetch the first points of q's cell (its hash slot prefetched earlier, so
    /// found in cache). No effect on any answer.
    void prefetchPoints(const Vec3f& q) const;
    /// Up to k points within max_dist (clamped to 2 cell()) of q, nearest first.
    void knn(const Vec3f& q, size_t k, float max_dist, std::vector<uint32_t>& idx, std::vector<float>& sq_dists) const;
    /// Cells holding at least one point.
    size_t cells() const { return count_; }
    size_t memoryBytes() const;

   private:
    struct Slot {
        uint64_t key = ~0ull;
        uint32_t begin = 0, end = 0;  ///< range of pts_ / index_
    };
    const Slot* find(int64_t x, int64_t y, int64_t z) const;
    /// Calls visit(begin, end) for the query's own cell, then for each cell up to `rings` (1 or
    /// 2) cells away whose box is nearer than bound() (squared), which the visits may shrink.
    /// Returns a lower bound on the squared distance from q to every cell within `rings` it did
    /// not visit (infinity: none left).
    template <class Visit, class Bound>
    float forCells(const Vec3f& q, int rings, Visit&& visit, Bound&& bound) const;

    double cell_ = 0;
    float inv_ = 0;
    std::vector<Slot> table_;  ///< open addressing, linear probing, power-of-two size
    uint64_t mask_ = 0;
    size_t count_ = 0;
    const std::vector<Vec3f>* pts_ = nullptr;  ///< the constructor's points
    std::vector<uint32_t> index_;              ///< indices into them, sorted by cell (empty: in cell order already)
};

}  // namespace superloc::map
