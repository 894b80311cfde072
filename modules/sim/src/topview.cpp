#include <superloc/sim/surface.h>
#include <superloc/sim/topview.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace superloc::sim {
namespace {

std::string fmt(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f", v);
    return b;
}

// Blue (low) -> red (high).
std::string heightColour(double f) {
    f = std::clamp(f, 0.0, 1.0);
    char b[16];
    std::snprintf(b, sizeof b, "#%02x%02x%02x", static_cast<int>(40 + 215 * f),
                  static_cast<int>(90 + 60 * (1 - std::abs(2 * f - 1))),
                  static_cast<int>(255 - 215 * f));
    return b;
}

}  // namespace

std::string topViewSvg(const Mesh& mesh, const std::vector<Vec3d>& traj,
                       const TopViewOptions& opt) {
    Vec3d lo, hi;
    mesh.bounds(lo, hi);
    if (!traj.empty()) {
        Vec3d tlo = traj.front(), thi = traj.front();
        for (const auto& p : traj) tlo = tlo.cwiseMin(p), thi = thi.cwiseMax(p);
        lo = lo.cwiseMax(tlo - Vec3d::Constant(opt.margin));
        hi = hi.cwiseMin(thi + Vec3d::Constant(opt.margin));
    }
    const double cell = std::max(opt.cell, std::max(hi.x() - lo.x(), hi.y() - lo.y()) / 4000);
    const int nx = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)));
    const int ny = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)));
    // Walls are steep surfaces at the trajectory's heights (a cut through the world just above
    // the sensor, so door lintels and tree crowns do not hide doors and trunks).
    double tz_lo = -1e300, tz_hi = 1e300;
    if (!traj.empty()) {
        tz_lo = tz_hi = traj.front().z();
        for (const auto& p : traj) tz_lo = std::min(tz_lo, p.z()), tz_hi = std::max(tz_hi, p.z());
        tz_lo -= 2.0;
        tz_hi += 0.4;
    }
    // 0 empty, 1 floor (upward-facing), 2 wall (steep).
    std::vector<uint8_t> grid(static_cast<size_t>(nx) * ny, 0);
    const PointCloud s = sampleSurface(mesh, cell / 3, 1, [&](const Vec3f& q) {
        return q.x() >= lo.x() && q.y() >= lo.y() && q.x() <= hi.x() && q.y() <= hi.y();
    });
    for (size_t i = 0; i < s.size(); ++i) {
        const int ix = static_cast<int>((s.points[i].x() - lo.x()) / cell);
        const int iy = static_cast<int>((s.points[i].y() - lo.y()) / cell);
        if (ix < 0 || iy < 0 || ix >= nx || iy >= ny) continue;
        const float nz = s.normals[i].z();
        uint8_t& g = grid[static_cast<size_t>(iy) * nx + ix];
        if (std::abs(nz) < 0.6f) {
            if (s.points[i].z() >= tz_lo && s.points[i].z() <= tz_hi) g = 2;
        } else if (nz > 0 && g == 0) {
            g = 1;
        }
    }
    const double px = std::min(50.0, opt.max_pixels / (std::max(nx, ny) * cell));  // px per metre
    const double W = nx * cell * px, H = ny * cell * px + 30;
    const auto X = [&](double x) { return (x - lo.x()) * px; };
    const auto Y = [&](double y) { return (hi.y() - y) * px + 30; };  // north up

    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << fmt(W) << "\" height=\"" << fmt(H)
      << "\" viewBox=\"0 0 " << fmt(W) << ' ' << fmt(H) << "\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    for (int cls = 1; cls <= 2; ++cls) {
        o << "<g fill=\"" << (cls == 1 ? "#dddddd" : "#333333") << "\">\n";
        for (int iy = 0; iy < ny; ++iy)
            for (int ix = 0; ix < nx;) {
                if (grid[static_cast<size_t>(iy) * nx + ix] != cls) {
                    ++ix;
                    continue;
                }
                int end = ix;
                while (end < nx && grid[static_cast<size_t>(iy) * nx + end] == cls) ++end;
                o << "<rect x=\"" << fmt(X(lo.x() + ix * cell)) << "\" y=\""
                  << fmt(Y(lo.y() + (iy + 1) * cell)) << "\" width=\""
                  << fmt((end - ix) * cell * px) << "\" height=\"" << fmt(cell * px + 0.3)
                  << "\"/>\n";
                ix = end;
            }
        o << "</g>\n";
    }
    if (traj.size() >= 2) {
        double zlo = traj.front().z(), zhi = zlo;
        for (const auto& p : traj) zlo = std::min(zlo, p.z()), zhi = std::max(zhi, p.z());
        const size_t chunk = std::max<size_t>(2, traj.size() / 200);
        for (size_t i = 0; i + 1 < traj.size(); i += chunk) {
            const size_t j = std::min(traj.size() - 1, i + chunk);
            const double f = zhi - zlo > 0.2 ? (traj[i].z() - zlo) / (zhi - zlo) : 0.0;
            o << "<polyline fill=\"none\" stroke-width=\"2\" stroke=\"" << heightColour(f)
              << "\" points=\"";
            for (size_t k = i; k <= j; ++k)
                o << fmt(X(traj[k].x())) << ',' << fmt(Y(traj[k].y())) << ' ';
            o << "\"/>\n";
        }
        o << "<circle cx=\"" << fmt(X(traj.front().x())) << "\" cy=\"" << fmt(Y(traj.front().y()))
          << "\" r=\"5\" fill=\"green\"/>\n"
          << "<rect x=\"" << fmt(X(traj.back().x()) - 4) << "\" y=\"" << fmt(Y(traj.back().y()) - 4)
          << "\" width=\"8\" height=\"8\" fill=\"red\"/>\n";
        if (zhi - zlo > 0.2)
            o << "<text x=\"" << fmt(W - 250)
              << "\" y=\"20\" font-family=\"sans-serif\" font-size=\"13\">"
              << "path colour: z " << fmt(zlo) << " m (blue) to " << fmt(zhi)
              << " m (red)</text>\n";
    }
    const double bar = px * 10 > 300 ? 1 : (px * 10 > 40 ? 10 : 50);
    o << "<line x1=\"10\" y1=\"" << fmt(H - 10) << "\" x2=\"" << fmt(10 + bar * px) << "\" y2=\""
      << fmt(H - 10) << "\" stroke=\"black\" stroke-width=\"3\"/>\n"
      << "<text x=\"12\" y=\"" << fmt(H - 15) << "\" font-family=\"sans-serif\" font-size=\"12\">"
      << fmt(bar) << " m</text>\n"
      << "<text x=\"10\" y=\"20\" font-family=\"sans-serif\" font-size=\"15\">" << opt.title
      << "</text>\n</svg>\n";
    return o.str();
}

}  // namespace superloc::sim
