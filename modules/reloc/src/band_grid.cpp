// Height-band grids of the prior map and their OR-pooled pyramid (doc/relocalization.md §1).
#include <superloc/reloc/band_grid.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <stdexcept>

namespace superloc::reloc {

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
}

int BandGridPyramid::cellIndexX(double x) const {
    return static_cast<int>(std::floor((x - x0_) / params_.resolution));
}
int BandGridPyramid::cellIndexY(double y) const {
    return static_cast<int>(std::floor((y - y0_) / params_.resolution));
}

int BandGridPyramid::groundIndex(double x, double y) const {
    if (gnx_ == 0 || gny_ == 0) return -1;
    const int ix = std::clamp(static_cast<int>(std::floor((x - gx0_) / params_.ground_cell)), 0, gnx_ - 1);
    const int iy = std::clamp(static_cast<int>(std::floor((y - gy0_) / params_.ground_cell)), 0, gny_ - 1);
    return iy * gnx_ + ix;
}

double BandGridPyramid::groundAt(double x, double y) const {
    const int i = groundIndex(x, y);
    return i < 0 ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(ground_[static_cast<size_t>(i)]);
}

bool BandGridPyramid::groundObserved(double x, double y) const {
    const int i = groundIndex(x, y);
    if (i < 0) return false;
    // Outside the ground grid the clamped index would lie: check the range explicitly.
    const double fx = (x - gx0_) / params_.ground_cell, fy = (y - gy0_) / params_.ground_cell;
    if (fx < 0 || fy < 0 || fx >= gnx_ || fy >= gny_) return false;
    return observed_[static_cast<size_t>(i)] != 0;
}

uint32_t BandGridPyramid::bandBit(double zrel) const {
    if (!(zrel >= params_.clearance)) return 0;
    const int b = static_cast<int>((zrel - params_.clearance) / params_.band_height);
    return b < params_.bands ? (1u << b) : 0u;
}

void BandGridPyramid::buildGround(const std::vector<Vec3f>& points) {
    const double gc = params_.ground_cell;
    // Columns: counting sort of the points' z by column.
    const size_t n = static_cast<size_t>(gnx_) * static_cast<size_t>(gny_);
    std::vector<uint32_t> start(n + 1, 0);
    std::vector<int> col(points.size(), -1);
    for (size_t i = 0; i < points.size(); ++i) {
        const auto& p = points[i];
        if (!p.allFinite()) continue;
        const int ix = static_cast<int>(std::floor((p.x() - gx0_) / gc));
        const int iy = static_cast<int>(std::floor((p.y() - gy0_) / gc));
        if (ix < 0 || iy < 0 || ix >= gnx_ || iy >= gny_) continue;
        col[i] = iy * gnx_ + ix;
        ++start[static_cast<size_t>(col[i]) + 1];
    }
    for (size_t c = 0; c < n; ++c) start[c + 1] += start[c];
    std::vector<float> z(start[n]);
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < points.size(); ++i)
        if (col[i] >= 0) z[fill[static_cast<size_t>(col[i])]++] = points[i].z();
    // Robust lowest point per column: the lowest z with >= 3 points within 0.3 m above it (a
    // stray point below the ground, e.g. a reflection, is skipped).
    std::vector<float> raw(n, kNaN);
    for (size_t c = 0; c < n; ++c) {
        auto b = z.begin() + start[c], e = z.begin() + start[c + 1];
        if (b == e) continue;
        std::sort(b, e);
        const long cnt = e - b;
        raw[c] = *b;
        if (cnt < 3) continue;
        for (auto it = b; it != e; ++it) {
            if (std::upper_bound(it, e, *it + 0.3f) - it >= 3) {
                raw[c] = *it;
                break;
            }
        }
    }
    // A column whose lowest points are not the ground (a canopy, a wall seen from above) takes
    // its 3 x 3 neighbours' minimum.
    ground_.assign(n, kNaN);
    observed_.assign(n, 0);
    for (int iy = 0; iy < gny_; ++iy)
        for (int ix = 0; ix < gnx_; ++ix) {
            float m = kNaN;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int jx = ix + dx, jy = iy + dy;
                    if (jx < 0 || jy < 0 || jx >= gnx_ || jy >= gny_) continue;
                    const float v = raw[static_cast<size_t>(jy * gnx_ + jx)];
                    if (!std::isnan(v) && (std::isnan(m) || v < m)) m = v;
                }
            const size_t c = static_cast<size_t>(iy * gnx_ + ix);
            ground_[c] = m;
            observed_[c] = std::isnan(m) ? 0 : 1;
        }
    // Unobserved columns: the value of the nearest observed one (breadth-first).
    std::deque<int> q;
    for (size_t c = 0; c < n; ++c)
        if (observed_[c]) q.push_back(static_cast<int>(c));
    while (!q.empty()) {
        const int c = q.front();
        q.pop_front();
        const int ix = c % gnx_, iy = c / gnx_;
        const int nb[4][2] = {{ix - 1, iy}, {ix + 1, iy}, {ix, iy - 1}, {ix, iy + 1}};
        for (const auto& b : nb) {
            if (b[0] < 0 || b[1] < 0 || b[0] >= gnx_ || b[1] >= gny_) continue;
            const size_t j = static_cast<size_t>(b[1] * gnx_ + b[0]);
            if (!std::isnan(ground_[j])) continue;
            ground_[j] = ground_[static_cast<size_t>(c)];
            q.push_back(static_cast<int>(j));
        }
    }
}

BandGridPyramid::BandGridPyramid(const std::vector<Vec3f>& points, const Params& params) : params_(params) {
    if (!(params.resolution > 0) || params.levels < 1 || params.levels > 12 || params.bands < 1 ||
        params.bands > 32 || !(params.band_height > 0) || !(params.ground_cell > 0) || params.dilate_cells < 0)
        throw std::invalid_argument("BandGridPyramid: bad parameters");
    Eigen::AlignedBox3f box;
    for (const auto& p : points)
        if (p.allFinite()) box.extend(p);
    bands_.assign(static_cast<size_t>(params.levels), {});
    valid_.assign(static_cast<size_t>(params.levels), {});
    if (box.isEmpty()) return;

    // Ground grid over the map's xy extent + one column.
    const double gc = params.ground_cell;
    gx0_ = std::floor(box.min().x() / gc) * gc - gc;
    gy0_ = std::floor(box.min().y() / gc) * gc - gc;
    gnx_ = static_cast<int>(std::ceil((box.max().x() - gx0_) / gc)) + 2;
    gny_ = static_cast<int>(std::ceil((box.max().y() - gy0_) / gc)) + 2;
    buildGround(points);

    // Band grid: the map's extent + the position margin on every side.
    const double r = params.resolution;
    const double pad = params.position_margin + (params.dilate_cells + 1) * r;
    x0_ = std::floor((box.min().x() - pad) / r) * r;
    y0_ = std::floor((box.min().y() - pad) / r) * r;
    nx_ = static_cast<int>(std::ceil((box.max().x() + pad - x0_) / r)) + 1;
    ny_ = static_cast<int>(std::ceil((box.max().y() + pad - y0_) / r)) + 1;
    const size_t cells = static_cast<size_t>(nx_) * static_cast<size_t>(ny_);
    std::vector<uint32_t> g0(cells, 0);
    const double tol = params.z_tolerance;
    for (const auto& p : points) {
        if (!p.allFinite()) continue;
        const int ix = cellIndexX(p.x()), iy = cellIndexY(p.y());
        if (ix < 0 || iy < 0 || ix >= nx_ || iy >= ny_) continue;
        const double zrel = p.z() - groundAt(p.x(), p.y());
        if (zrel + tol < params.clearance) continue;
        const int b0 = std::max(0, static_cast<int>(std::floor((zrel - tol - params.clearance) / params.band_height)));
        const int b1 = std::min(params.bands - 1,
                                static_cast<int>(std::floor((zrel + tol - params.clearance) / params.band_height)));
        uint32_t bits = 0;
        for (int b = b0; b <= b1; ++b) bits |= 1u << b;
        g0[static_cast<size_t>(iy) * nx_ + ix] |= bits;
    }
    // Dilation by dilate_cells (separable OR: rows, then columns).
    const int d = params.dilate_cells;
    if (d > 0) {
        std::vector<uint32_t> tmp(cells, 0);
        for (int iy = 0; iy < ny_; ++iy)
            for (int ix = 0; ix < nx_; ++ix) {
                uint32_t v = 0;
                for (int k = std::max(0, ix - d); k <= std::min(nx_ - 1, ix + d); ++k) v |= g0[static_cast<size_t>(iy) * nx_ + k];
                tmp[static_cast<size_t>(iy) * nx_ + ix] = v;
            }
        for (int iy = 0; iy < ny_; ++iy)
            for (int ix = 0; ix < nx_; ++ix) {
                uint32_t v = 0;
                for (int k = std::max(0, iy - d); k <= std::min(ny_ - 1, iy + d); ++k) v |= tmp[static_cast<size_t>(k) * nx_ + ix];
                g0[static_cast<size_t>(iy) * nx_ + ix] = v;
            }
    }
    occupied_ = static_cast<size_t>(std::count_if(g0.begin(), g0.end(), [](uint32_t v) { return v != 0; }));

    // Sensor positions: cells whose centre lies within position_margin of an observed column.
    std::vector<uint8_t> v0(cells, 0);
    {
        const int m = static_cast<int>(std::ceil(params.position_margin / gc));
        std::vector<uint8_t> near(observed_.size(), 0);
        for (int iy = 0; iy < gny_; ++iy)
            for (int ix = 0; ix < gnx_; ++ix) {
                if (!observed_[static_cast<size_t>(iy * gnx_ + ix)]) continue;
                for (int dy = -m; dy <= m; ++dy)
                    for (int dx = -m; dx <= m; ++dx) {
                        const int jx = ix + dx, jy = iy + dy;
                        if (jx < 0 || jy < 0 || jx >= gnx_ || jy >= gny_ || dx * dx + dy * dy > m * m) continue;
                        near[static_cast<size_t>(jy * gnx_ + jx)] = 1;
                    }
            }
        for (int iy = 0; iy < ny_; ++iy)
            for (int ix = 0; ix < nx_; ++ix) {
                const double x = cellX(ix), y = cellY(iy);
                const double fx = (x - gx0_) / gc, fy = (y - gy0_) / gc;
                if (fx < 0 || fy < 0 || fx >= gnx_ || fy >= gny_) continue;
                v0[static_cast<size_t>(iy) * nx_ + ix] = near[static_cast<size_t>(groundIndex(x, y))];
            }
    }

    // Pyramid: level k = OR of level k-1 at (x, y), (x+s, y), (x, y+s), (x+s, y+s), s = 2^(k-1).
    bands_[0] = std::move(g0);
    valid_[0] = std::move(v0);
    for (int k = 1; k < params.levels; ++k) {
        const int s = 1 << (k - 1);
        const auto& pb = bands_[static_cast<size_t>(k - 1)];
        const auto& pv = valid_[static_cast<size_t>(k - 1)];
        auto& b = bands_[static_cast<size_t>(k)];
        auto& v = valid_[static_cast<size_t>(k)];
        b.assign(cells, 0);
        v.assign(cells, 0);
        for (int iy = 0; iy < ny_; ++iy)
            for (int ix = 0; ix < nx_; ++ix) {
                const size_t c = static_cast<size_t>(iy) * nx_ + ix;
                uint32_t bb = pb[c];
                uint8_t vv = pv[c];
                const bool rx = ix + s < nx_, ry = iy + s < ny_;
                if (rx) bb |= pb[c + s], vv |= pv[c + s];
                if (ry) bb |= pb[c + static_cast<size_t>(s) * nx_], vv |= pv[c + static_cast<size_t>(s) * nx_];
                if (rx && ry) bb |= pb[c + static_cast<size_t>(s) * nx_ + s], vv |= pv[c + static_cast<size_t>(s) * nx_ + s];
                b[c] = bb;
                v[c] = vv;
            }
    }
}

size_t BandGridPyramid::memoryBytes() const {
    size_t m = sizeof(*this);
    for (const auto& b : bands_) m += b.capacity() * sizeof(uint32_t);
    for (const auto& v : valid_) m += v.capacity();
    m += ground_.capacity() * sizeof(float) + observed_.capacity();
    return m;
}

}  // namespace superloc::reloc
