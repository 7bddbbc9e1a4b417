#include "field/field_sampler.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "util/parallel.hpp"

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

// One axis of a lookup ready for the inner loop: the two nodes' offsets into the values (index
// times the axis's stride) and their weights 1 - t and t, the products trilinear forms.
struct AxisLookup {
  std::size_t offset[2];
  double w[2];
};

AxisLookup axis_lookup(const AxisSample& s, std::size_t stride) {
  return {{s.i[0] * stride, s.i[1] * stride}, {1 - s.t, s.t}};
}

// trilinear's arithmetic, term for term, on prepared lookups.
double trilinear(const float* v, const AxisLookup& x, const AxisLookup& y, const AxisLookup& z) {
  double acc = 0.0;
  for (int k = 0; k < 8; ++k) {
    const int bx = k & 1, by = (k >> 1) & 1, bz = (k >> 2) & 1;
    acc += x.w[bx] * y.w[by] * z.w[bz] * v[x.offset[bx] + y.offset[by] + z.offset[bz]];
  }
  return acc;
}

// A level's axis lookups at every base-grid coordinate of one axis, shifted by -h, 0 and +h
// (the level's cell): the central differences of all base nodes share them.
std::vector<std::array<AxisLookup, 3>> axis_table(const Grid3& level, const Grid3& base, int a) {
  const std::size_t nx = level.dims.x, stride = a == 0 ? 1 : (a == 1 ? nx : nx * level.dims.y);
  std::vector<std::array<AxisLookup, 3>> out(base.dims[a]);
  for (unsigned k = 0; k < base.dims[a]; ++k) {
    const double p = base.origin[a] + base.cell * double(k);
    out[k] = {axis_lookup(axis_sample(level, a, p - level.cell), stride), axis_lookup(axis_sample(level, a, p), stride),
              axis_lookup(axis_sample(level, a, p + level.cell), stride)};
  }
  return out;
}

// ψ̃ and the averaged gradient at base node (x, y, z), as documented for precompute_field_gradient.
using LookupTables = std::vector<std::array<std::vector<std::array<AxisLookup, 3>>, 3>>;  // [level][axis][coord]

glm::vec4 node_field(const std::vector<Grid3>& pyramid, const LookupTables& tables, unsigned x, unsigned y, unsigned z) {
  glm::dvec3 grad(0.0);
  double value = 0.0;
  for (std::size_t l = 0; l < pyramid.size(); ++l) {
    const float* v = pyramid[l].values.data();
    const double h = pyramid[l].cell;
    const std::array<AxisLookup, 3>& sx = tables[l][0][x];
    const std::array<AxisLookup, 3>& sy = tables[l][1][y];
    const std::array<AxisLookup, 3>& sz = tables[l][2][z];
    value += trilinear(v, sx[1], sy[1], sz[1]);
    grad.x += (trilinear(v, sx[2], sy[1], sz[1]) - trilinear(v, sx[0], sy[1], sz[1])) / (2.0 * h);
    grad.y += (trilinear(v, sx[1], sy[2], sz[1]) - trilinear(v, sx[1], sy[0], sz[1])) / (2.0 * h);
    grad.z += (trilinear(v, sx[1], sy[1], sz[2]) - trilinear(v, sx[1], sy[1], sz[0])) / (2.0 * h);
  }
  const double levels = double(pyramid.size());
  return glm::vec4(float(value / levels), glm::vec3(grad / levels));
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
  LookupTables tables(pyramid.size());
  for (std::size_t l = 0; l < pyramid.size(); ++l)
    for (int a = 0; a < 3; ++a) tables[l][a] = axis_table(pyramid[l], base, a);
  auto slab = [&](unsigned z0, unsigned z1) {
    for (unsigned z = z0; z < z1; ++z)
      for (unsigned y = 0; y < base.dims.y; ++y)
        for (unsigned x = 0; x < base.dims.x; ++x) out.values[base.index(x, y, z)] = node_field(pyramid, tables, x, y, z);
  };
  // Each node is computed on its own, so splitting the z range cannot change a value.
  const unsigned mid = base.dims.z / 2;
  parallel_pair([&] { slab(0u, mid); }, [&] { slab(mid, base.dims.z); });
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
