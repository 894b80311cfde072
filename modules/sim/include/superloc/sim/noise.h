// Seeded procedural noise for rough surfaces, and independent random streams.
#pragma once

#include <superloc/core/types.h>

#include <cstdint>

namespace superloc::sim {

/// A seed for one purpose ("lidar", "imu", ...) derived from the run's seed, so that changing
/// one part of the simulation never shifts another part's random numbers.
uint64_t streamSeed(uint64_t seed, const char* purpose);

/// 3-D value noise (trilinear lattice noise with quintic fade), summed over octaves: smooth,
/// deterministic, values roughly in [-1, 1].
class FractalNoise {
 public:
    FractalNoise(uint64_t seed, double wavelength, int octaves = 3, double persistence = 0.5);
    double operator()(const Vec3d& p) const;

 private:
    double lattice(int64_t x, int64_t y, int64_t z, int octave) const;
    double valueNoise(const Vec3d& p, int octave) const;
    uint64_t seed_;
    double inv_wavelength_;
    int octaves_;
    double persistence_;
};

}  // namespace superloc::sim
