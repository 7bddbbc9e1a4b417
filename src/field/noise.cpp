#include "field/noise.hpp"

#include <cmath>

namespace fracref {
namespace {

// Ken Perlin's permutation, from the 2002 reference implementation.
constexpr std::array<std::uint8_t, 256> kReferencePermutation = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,
    103, 30,  69,  142, 8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,
    0,   26,  197, 62,  94,  252, 219, 203, 117, 35,  11,  32,  57,  177, 33,  88,  237, 149,
    56,  87,  174, 20,  125, 136, 171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166,
    77,  146, 158, 231, 83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,  55,  46,
    245, 40,  244, 102, 143, 54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187,
    208, 89,  18,  169, 200, 196, 135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186,
    3,   64,  52,  217, 226, 250, 124, 123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212,
    207, 206, 59,  227, 47,  16,  58,  17,  182, 189, 28,  42,  223, 183, 170, 213, 119, 248,
    152, 2,   44,  154, 163, 70,  221, 153, 101, 155, 167, 43,  172, 9,   129, 22,  39,  253,
    19,  98,  108, 110, 79,  113, 224, 232, 178, 185, 112, 104, 218, 246, 97,  228, 251, 34,
    242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,  51,  145, 235, 249, 14,  239, 107,
    49,  192, 214, 31,  181, 199, 106, 157, 184, 84,  204, 176, 115, 121, 50,  45,  127, 4,
    150, 254, 138, 236, 205, 93,  222, 114, 67,  29,  24,  72,  243, 141, 128, 195, 78,  66,
    215, 61,  156, 180};

double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
double lerp(double t, double a, double b) { return a + t * (b - a); }

// Perlin's grad(hash, x, y, z) as a table of the 16 gradients his bit tests select
// (u = h<8 ? x : y; v = h<4 ? y : h==12||h==14 ? x : z; signs from bits 0 and 1), without the
// unpredictable branches. Every product is by 0 or ±1 and one term is always 0, so the result
// is the reference's ±u ± v exactly (up to the sign of a zero).
constexpr double kGradients[16][3] = {
    {1, 1, 0},  {-1, 1, 0},  {1, -1, 0},  {-1, -1, 0},  // h = 0..3:  ±x ± y
    {1, 0, 1},  {-1, 0, 1},  {1, 0, -1},  {-1, 0, -1},  // h = 4..7:  ±x ± z
    {0, 1, 1},  {0, -1, 1},  {0, 1, -1},  {0, -1, -1},  // h = 8..11: ±y ± z
    {1, 1, 0},  {0, -1, 1},  {-1, 1, 0},  {0, -1, -1},  // h = 12..15: y+x, -y+z, y-x, -y-z
};

double grad(int hash, double x, double y, double z) {
  const double* g = kGradients[hash & 15];
  return g[0] * x + g[1] * y + g[2] * z;
}

// Splits v into its lattice cell floor(v) mod 256 (in [0, 255]) and the fraction v - floor(v),
// exactly for any finite v: the Java reference's (int) cast would overflow past 2^31. Below
// 2^62 an int64 conversion gives the floor without a libm call (every double that large is an
// integer, held exactly by int64, and & 255 is the non-negative residue in two's complement).
// Beyond, v is an integer and dividing by 256 is exact, so the wrap introduces no rounding.
int split_lattice(double& v) {
  if (std::abs(v) < 0x1p62) {
    std::int64_t i = static_cast<std::int64_t>(v);
    i -= v < static_cast<double>(i);
    v -= static_cast<double>(i);
    return static_cast<int>(i & 255);
  }
  const int index = static_cast<int>(v - 256.0 * std::floor(v / 256.0));
  v = 0.0;
  return index;
}

double improved_noise(const std::uint8_t* p, double x, double y, double z) {
  const int X = split_lattice(x), Y = split_lattice(y), Z = split_lattice(z);
  const double u = fade(x), v = fade(y), w = fade(z);
  const int A = p[X] + Y, AA = p[A] + Z, AB = p[A + 1] + Z;
  const int B = p[X + 1] + Y, BA = p[B] + Z, BB = p[B + 1] + Z;
  return lerp(w,
              lerp(v, lerp(u, grad(p[AA], x, y, z), grad(p[BA], x - 1, y, z)),
                   lerp(u, grad(p[AB], x, y - 1, z), grad(p[BB], x - 1, y - 1, z))),
              lerp(v, lerp(u, grad(p[AA + 1], x, y, z - 1), grad(p[BA + 1], x - 1, y, z - 1)),
                   lerp(u, grad(p[AB + 1], x, y - 1, z - 1),
                        grad(p[BB + 1], x - 1, y - 1, z - 1))));
}

const std::array<std::uint8_t, 512>& reference_table() {
  static const std::array<std::uint8_t, 512> table = [] {
    std::array<std::uint8_t, 512> t{};
    for (int i = 0; i < 256; ++i) t[i] = t[i + 256] = kReferencePermutation[i];
    return t;
  }();
  return table;
}

// Uniform in [0, bound) by rejection: values below 2^64 mod bound are redrawn, so every
// residue is equally likely.
std::uint64_t uniform_below(std::uint64_t& state, std::uint64_t bound) {
  const std::uint64_t reject_below = (0 - bound) % bound;
  for (;;) {
    const std::uint64_t r = splitmix64(state);
    if (r >= reject_below) return r % bound;
  }
}

template <bool kAbsolute>
double octave_sum(const PerlinNoise& noise, glm::dvec3 p, int octaves, double lacunarity,
                  double gain) {
  double sum = 0.0, weight = 1.0, total = 0.0, frequency = 1.0;
  for (int i = 0; i < octaves; ++i) {
    const double n = noise(p * frequency);
    sum += weight * (kAbsolute ? std::abs(n) : n);
    total += weight;
    weight *= gain;
    frequency *= lacunarity;
  }
  return total > 0.0 ? sum / total : 0.0;
}

}  // namespace

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double perlin_noise(double x, double y, double z) {
  return improved_noise(reference_table().data(), x, y, z);
}

PerlinNoise::PerlinNoise(std::uint64_t seed) : seed_(seed), p_(reference_table()) {
  if (seed == 0) return;
  std::array<std::uint8_t, 256> perm = kReferencePermutation;
  std::uint64_t state = seed;
  for (std::uint64_t i = 255; i >= 1; --i) {
    const std::uint64_t j = uniform_below(state, i + 1);
    std::swap(perm[i], perm[j]);
  }
  for (int i = 0; i < 256; ++i) p_[i] = p_[i + 256] = perm[i];
}

double PerlinNoise::operator()(double x, double y, double z) const {
  return improved_noise(p_.data(), x, y, z);
}

std::array<std::uint8_t, 256> PerlinNoise::permutation() const {
  std::array<std::uint8_t, 256> perm{};
  for (int i = 0; i < 256; ++i) perm[i] = p_[i];
  return perm;
}

double fbm(const PerlinNoise& noise, glm::dvec3 p, int octaves, double lacunarity, double gain) {
  return octave_sum<false>(noise, p, octaves, lacunarity, gain);
}

double turbulence(const PerlinNoise& noise, glm::dvec3 p, int octaves, double lacunarity,
                  double gain) {
  return octave_sum<true>(noise, p, octaves, lacunarity, gain);
}

}  // namespace fracref
