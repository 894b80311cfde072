// Ray-cast scenes for the risk tests: a sensor at the origin inside axis-aligned planes
// (floor, walls, ...). Each return gives a point-to-plane correspondence with the plane's
// normal flipped toward the sensor, as the localizer would produce at the true pose.
#pragma once

#include <superloc/risk/alignment_risk.h>

#include <cmath>
#include <vector>

namespace superloc::risk::testing {

/// The plane {x : x[axis] = offset}.
struct AxisPlane {
    int axis;
    double offset;
};

/// Casts n_az x n_el rays (azimuth over 360 deg, elevation evenly in [el_min, el_max] deg)
/// from the origin; each ray keeps its nearest plane hit within max_range.
inline std::vector<Correspondence> castScene(const std::vector<AxisPlane>& planes, int n_az = 360,
                                             int n_el = 32, double el_min = -45, double el_max = 45,
                                             double max_range = 30) {
    std::vector<Correspondence> out;
    const double deg = M_PI / 180;
    for (int e = 0; e < n_el; ++e) {
        const double el = (el_min + (el_max - el_min) * (e + 0.5) / n_el) * deg;
        for (int a = 0; a < n_az; ++a) {
            const double az = (360.0 * (a + 0.5) / n_az) * deg;
            const Vec3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
            double best = max_range;
            int hit = -1;
            for (size_t k = 0; k < planes.size(); ++k) {
                const double dk = d[planes[k].axis];
                if (std::abs(dk) < 1e-12) continue;
                const double t = planes[k].offset / dk;
                if (t > 0 && t < best) best = t, hit = static_cast<int>(k);
            }
            if (hit < 0) continue;
            Correspondence c;
            c.p = best * d;
            c.n = Vec3d::Zero();
            // Toward the sensor: against the ray direction along the plane's axis.
            c.n[planes[hit].axis] = planes[hit].offset > 0 ? -1.0 : 1.0;
            out.push_back(c);
        }
    }
    return out;
}

}  // namespace superloc::risk::testing
