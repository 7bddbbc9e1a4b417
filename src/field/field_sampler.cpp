#include "field/field_sampler.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <thread>

namespace fracref {
namespace {

double clamp_coord(double g, unsigned n) { return std::clamp(g, 0.0, double(n > 0 ? n - 1 : 0)); }

// One axis of a trilinear lookup: the two nodes around coordinate `coord` and the weight of the
// second, the point clamped into the grid.
struct AxisSample {
  unsigned i[2];
  double t;
};

AxisSample axis_sample(const Grid3& grid, int a, double coord) {
  const unsigned n = grid.dims[a];
  const double c = clamp_coord((coord - grid.origin[a]) / grid.cell, n);
  const unsigned i0 = n >= 2 ? std::min<unsigned>(unsigned(std::floor(c)), n - 2) : 0;
  return {{i0, n >= 2 ? i0 + 1 : 0}, n >= 2 ? c - i0 : 0.0};
}

double trilinear(const Grid3& grid, const AxisSample& x, const AxisSample& y, const AxisSample& z) {
  double acc = 0.0;
  for (int k = 0; k < 8; ++k) {
    const int bx = k & 1, by = (k >> 1) & 1, bz = (k >> 2) & 1;
    const double w = (bx ? x.t : 1 - x.t) * (by ? y.t : 1 - y.t) * (bz ? z.t : 1 - z.t);
    acc += w * grid.at(x.i[bx], y.i[by], z.i[bz]);
  }
  return acc;
}

// A level's axis lookups at every base-grid coordinate of one axis, shifted by -h, 0 and +h
// (the level's cell): the central differences of all base nodes share them.
std::vector<std::array<AxisSample, 3>> axis_table(const Grid3& level, const Grid3& base, int a) {
  std::vector<std::array<AxisSample, 3>> out(base.dims[a]);
  for (unsigned k = 0; k < base.dims[a]; ++k) {
    const double p = base.origin[a] + base.cell * double(k);
    out[k] = {axis_sample(level, a, p - level.cell), axis_sample(level, a, p), axis_sample(level, a, p + level.cell)};
  }
  return out;
}

}  // namespace

double sample_trilinear(const Grid3& grid, const glm::dvec3& p) {
  return trilinear(grid, axis_sample(grid, 0, p.x), axis_sample(grid, 1, p.y), axis_sample(grid, 2, p.z));
}

// The same arithmetic as sample_trilinear at p and p ± h e_a (a shift along one axis leaves the
// other coordinates exactly as they are), with each axis's lookups computed once per level.
FieldGrid4 precompute_field_gradient(const std::vector<Grid3>& pyramid) {
  const Grid3& base = pyramid.front();
  FieldGrid4 out{base.dims, base.origin, base.cell, std::vector<glm::vec4>(base.size())};
  const double levels = double(pyramid.size());
  std::vector<std::array<std::vector<std::array<AxisSample, 3>>, 3>> tables(pyramid.size());
  for (std::size_t l = 0; l < pyramid.size(); ++l)
    for (int a = 0; a < 3; ++a) tables[l][a] = axis_table(pyramid[l], base, a);
  auto slab = [&](unsigned z0, unsigned z1) {
    for (unsigned z = z0; z < z1; ++z)
      for (unsigned y = 0; y < base.dims.y; ++y)
        for (unsigned x = 0; x < base.dims.x; ++x) {
          glm::dvec3 grad(0.0);
          double value = 0.0;
          for (std::size_t l = 0; l < pyramid.size(); ++l) {
            const Grid3& level = pyramid[l];
            const double h = level.cell;
            const std::array<AxisSample, 3> s[3] = {tables[l][0][x], tables[l][1][y], tables[l][2][z]};
            value += trilinear(level, s[0][1], s[1][1], s[2][1]);
            for (int a = 0; a < 3; ++a) {
              AxisSample plus[3] = {s[0][1], s[1][1], s[2][1]}, minus[3] = {s[0][1], s[1][1], s[2][1]};
              plus[a] = s[a][2];
              minus[a] = s[a][0];
              grad[a] += (trilinear(level, plus[0], plus[1], plus[2]) - trilinear(level, minus[0], minus[1], minus[2])) /
                         (2.0 * h);
            }
          }
          out.values[base.index(x, y, z)] = glm::vec4(float(value / levels), glm::vec3(grad / levels));
        }
  };
  // Each node is computed on its own, so splitting the z range cannot change a value.
  std::thread other(slab, 0u, base.dims.z / 2);
  slab(base.dims.z / 2, base.dims.z);
  other.join();
  return out;
}

glm::vec4 sample_field(const FieldGrid4& f, const glm::vec3& p) {
  glm::vec3 g = (p - glm::vec3(f.origin)) / float(f.cell);
  glm::uvec3 i0;
  glm::vec3 t;
  for (int a = 0; a < 3; ++a) {
    float n1 = float(f.dims[a] - 1);
    float c = std::clamp(g[a], 0.0f, n1);
    i0[a] = std::min(unsigned(std::floor(c)), f.dims[a] - 2);
    t[a] = c - float(i0[a]);
  }
  auto at = [&](unsigned x, unsigned y, unsigned z) {
    return f.values[x + std::size_t(f.dims.x) * (y + std::size_t(f.dims.y) * z)];
  };
  glm::vec4 c00 = glm::mix(at(i0.x, i0.y, i0.z), at(i0.x + 1, i0.y, i0.z), t.x);
  glm::vec4 c10 = glm::mix(at(i0.x, i0.y + 1, i0.z), at(i0.x + 1, i0.y + 1, i0.z), t.x);
  glm::vec4 c01 = glm::mix(at(i0.x, i0.y, i0.z + 1), at(i0.x + 1, i0.y, i0.z + 1), t.x);
  glm::vec4 c11 = glm::mix(at(i0.x, i0.y + 1, i0.z + 1), at(i0.x + 1, i0.y + 1, i0.z + 1), t.x);
  return glm::mix(glm::mix(c00, c10, t.y), glm::mix(c01, c11, t.y), t.z);
}

}  // namespace fracref
