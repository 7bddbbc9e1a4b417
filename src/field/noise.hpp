#pragma once
// Ken Perlin's improved noise (SIGGRAPH 2002 reference implementation) in double precision, a
// seeded variant of it, and the two classic sums built on it: fBm and turbulence.
#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace fracref {

/// The supremum of |noise| for the improved-noise gradient set in 3D. The reference noise is
/// NOT bounded by 1: its extreme values are about ±1.0363 (rare; random samples stay within
/// [-1, 1] almost always). Materials that map noise to [0, 1] clamp.
inline constexpr double kPerlinNoiseBound = 1.0364;

/// Ken Perlin's improved noise, exactly his 2002 Java reference `ImprovedNoise.noise`: his
/// permutation table, fade 6t^5 - 15t^4 + 10t^3, the 12 gradients chosen by hash & 15, the same
/// operations in the same order, so e.g. perlin_noise(3.14, 42, 7) == 0.13691995878400012.
/// Zero at every integer lattice point; C2-continuous; periodic with period 256 on each axis.
/// \pre x, y, z finite (lattice coordinates are wrapped modulo 256 exactly, even for huge values).
double perlin_noise(double x, double y, double z);

/// Improved noise with a seeded permutation table.
/// Seed 0 is exactly the reference table (operator() == perlin_noise). Any other seed shuffles
/// the reference table by Fisher-Yates (i from 255 down to 1, j uniform in [0, i]) driven by the
/// splitmix64 stream started at `seed`, with j drawn by unbiased rejection (r % (i+1) after
/// rejecting r < 2^64 mod (i+1)). Plain integer arithmetic: the same table on every platform.
class PerlinNoise {
 public:
  explicit PerlinNoise(std::uint64_t seed = 0);

  /// The noise at p: in [-kPerlinNoiseBound, kPerlinNoiseBound], 0 at integer lattice points.
  double operator()(glm::dvec3 p) const { return (*this)(p.x, p.y, p.z); }
  double operator()(double x, double y, double z) const;

  std::uint64_t seed() const { return seed_; }
  /// The 256-entry permutation (a permutation of 0..255).
  std::array<std::uint8_t, 256> permutation() const;

 private:
  std::uint64_t seed_;
  std::array<std::uint8_t, 512> p_;  // the permutation twice, so p_[p_[X] + Y] needs no wrap
};

/// One step of splitmix64 (Steele, Lea, Flood 2014): advances `state` by 0x9E3779B97F4A7C15 and
/// returns the mixed value. The one portable generator fracref uses for seeded randomness.
std::uint64_t splitmix64(std::uint64_t& state);

/// Fractional Brownian motion, normalised:
///   fbm = Σ_{i<octaves} gain^i · noise(p · lacunarity^i) / Σ_{i<octaves} gain^i,
/// so it lies in [-kPerlinNoiseBound, kPerlinNoiseBound] like one octave (its spread is smaller).
/// \pre octaves >= 1, lacunarity > 0, gain > 0.
double fbm(const PerlinNoise& noise, glm::dvec3 p, int octaves, double lacunarity = 2.0,
           double gain = 0.5);

/// Perlin's turbulence, normalised the same way: Σ gain^i · |noise(p · lacunarity^i)| / Σ gain^i,
/// in [0, kPerlinNoiseBound]. \pre as fbm.
double turbulence(const PerlinNoise& noise, glm::dvec3 p, int octaves, double lacunarity = 2.0,
                  double gain = 0.5);

}  // namespace fracref
