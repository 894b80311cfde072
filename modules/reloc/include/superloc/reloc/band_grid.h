// The search structure of the global search (doc/relocalization.md §1): the prior map as a
// gravity-aligned 2-D grid whose cells hold one bit per *height band above the local ground*,
// and its max-pooled (OR-pooled) pyramid for branch-and-bound.
//
// Height above the local ground instead of absolute z makes the search independent of the
// sensor's height: a scan point's band comes from its height above the scan's own ground plane,
// a map point's from its height above the map's ground in its xy column. Level k holds, at
// cell (x, y), the OR of level 0 over the window [x, x + 2^k) x [y, y + 2^k): the hits of a
// scan at any translation of a node are bounded by the hits of its points in that level.
#pragma once

#include <superloc/core/types.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace superloc::reloc {

class BandGridPyramid {
   public:
    struct Params {
        double resolution = 0.25;    ///< [m] level-0 cell edge
        int levels = 7;              ///< pyramid levels; level k pools 2^k x 2^k cells
        double band_height = 0.5;    ///< [m] height band
        int bands = 24;              ///< bands above `clearance` (<= 32)
        double clearance = 0.3;      ///< [m] points lower than this above the ground are not scored
        double z_tolerance = 0.25;   ///< [m] a map point also marks the bands within this of its height
        int dilate_cells = 1;        ///< level 0: a cell also holds the bands of its neighbours within this
        double ground_cell = 1.0;    ///< [m] column edge of the ground-height grid
        double position_margin = 3;  ///< [m] sensor positions within this of an observed ground column
    };

    BandGridPyramid() = default;
    /// Builds the ground grid, the band grid and its pyramid from map points (map frame, z up).
    BandGridPyramid(const std::vector<Vec3f>& points, const Params& params);

    const Params& params() const { return params_; }
    int levels() const { return static_cast<int>(bands_.size()); }
    int nx() const { return nx_; }
    int ny() const { return ny_; }
    /// [m] map xy of the centre of level-0 cell (ix, iy).
    double cellX(int ix) const { return x0_ + (ix + 0.5) * params_.resolution; }
    double cellY(int iy) const { return y0_ + (iy + 0.5) * params_.resolution; }
    /// Level-0 cell index of a map coordinate (may be outside [0, n)).
    int cellIndexX(double x) const;
    int cellIndexY(double y) const;

    /// Band bits of level `level` at cell (ix, iy): the OR over the window [ix, ix + 2^level) x
    /// [iy, iy + 2^level) of level 0. A window that starts before the grid but reaches into it
    /// gets the window of cell 0 (a superset of its part inside: still an upper bound); 0 when
    /// the window misses the grid.
    uint32_t bits(int level, int ix, int iy) const {
        if (ix < 0) {
            if (ix + (1 << level) <= 0) return 0;
            ix = 0;
        }
        if (iy < 0) {
            if (iy + (1 << level) <= 0) return 0;
            iy = 0;
        }
        if (ix >= nx_ || iy >= ny_) return 0;
        return bands_[static_cast<size_t>(level)][static_cast<size_t>(iy) * nx_ + ix];
    }
    /// True when some sensor position of the window of (ix, iy) at `level` is a valid one
    /// (within position_margin of an observed ground column).
    bool positionValid(int level, int ix, int iy) const {
        if (static_cast<unsigned>(ix) >= static_cast<unsigned>(nx_) ||
            static_cast<unsigned>(iy) >= static_cast<unsigned>(ny_))
            return false;
        return valid_[static_cast<size_t>(level)][static_cast<size_t>(iy) * nx_ + ix] != 0;
    }
    /// Bit of the band at height `zrel` above the ground (a scan point), 0 when it is below
    /// `clearance` or above the top band.
    uint32_t bandBit(double zrel) const;

    /// [m] ground height of the map at (x, y): the column's robust lowest point, lowered to its
    /// 3 x 3 neighbours' minimum, filled from the nearest observed column where none was seen.
    /// NaN when the map has no point at all.
    double groundAt(double x, double y) const;
    /// The column of (x, y) (or one of its neighbours) held map points near its ground.
    bool groundObserved(double x, double y) const;

    /// Resident bytes of every grid.
    size_t memoryBytes() const;
    /// Occupied level-0 cells (any band).
    size_t occupiedCells() const { return occupied_; }

   private:
    void buildGround(const std::vector<Vec3f>& points);
    int groundIndex(double x, double y) const;

    Params params_;
    double x0_ = 0, y0_ = 0;  ///< [m] lower corner of level-0 cell (0, 0)
    int nx_ = 0, ny_ = 0;
    std::vector<std::vector<uint32_t>> bands_;  ///< per level, row-major [iy * nx + ix]
    std::vector<std::vector<uint8_t>> valid_;   ///< per level, sensor-position mask
    size_t occupied_ = 0;
    // Ground grid
    double gx0_ = 0, gy0_ = 0;
    int gnx_ = 0, gny_ = 0;
    std::vector<float> ground_;        ///< [m] filled ground height per column
    std::vector<uint8_t> observed_;    ///< column (or a neighbour) held map points
};

}  // namespace superloc::reloc
