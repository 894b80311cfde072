#include <superloc/sim/noise.h>

#include <cmath>

namespace superloc::sim {
namespace {

uint64_t splitmix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }

}  // namespace

uint64_t streamSeed(uint64_t seed, const char* purpose) {
    uint64_t h = 1469598103934665603ull;  // FNV-1a of the purpose
    for (const char* c = purpose; *c; ++c)
        h = (h ^ static_cast<unsigned char>(*c)) * 1099511628211ull;
    return splitmix64(seed ^ splitmix64(h));
}

FractalNoise::FractalNoise(uint64_t seed, double wavelength, int octaves, double persistence)
    : seed_(seed),
      inv_wavelength_(1.0 / wavelength),
      octaves_(octaves),
      persistence_(persistence) {}

double FractalNoise::lattice(int64_t x, int64_t y, int64_t z, int octave) const {
    uint64_t h = splitmix64(seed_ + static_cast<uint64_t>(octave));
    h = splitmix64(h ^ static_cast<uint64_t>(x));
    h = splitmix64(h ^ static_cast<uint64_t>(y));
    h = splitmix64(h ^ static_cast<uint64_t>(z));
    return (h >> 11) * (2.0 / 9007199254740992.0) - 1.0;  // uniform in [-1, 1)
}

double FractalNoise::valueNoise(const Vec3d& p, int octave) const {
    const double fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
    const auto x0 = static_cast<int64_t>(fx), y0 = static_cast<int64_t>(fy),
               z0 = static_cast<int64_t>(fz);
    const double u = fade(p.x() - fx), v = fade(p.y() - fy), w = fade(p.z() - fz);
    double acc = 0;
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx)
                acc += (dx ? u : 1 - u) * (dy ? v : 1 - v) * (dz ? w : 1 - w) *
                       lattice(x0 + dx, y0 + dy, z0 + dz, octave);
    return acc;
}

double FractalNoise::operator()(const Vec3d& p) const {
    double sum = 0, amp = 1, norm = 0, freq = inv_wavelength_;
    for (int o = 0; o < octaves_; ++o) {
        sum += amp * valueNoise(p * freq, o);
        norm += amp;
        amp *= persistence_;
        freq *= 2;
    }
    return sum / norm;
}

}  // namespace superloc::sim
