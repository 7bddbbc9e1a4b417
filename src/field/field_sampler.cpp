#include "field/field_sampler.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "field/pyramid.hpp"
#include "util/error.hpp"
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

// The same at grid coordinate g (in cells from the origin) of an axis of n nodes.
AxisSample index_sample(unsigned n, double g) {
  const double c = clamp_coord(g, n);
  const unsigned i0 = n >= 2 ? std::min<unsigned>(unsigned(std::floor(c)), n - 2) : 0;
  return {{i0, n >= 2 ? i0 + 1 : 0}, n >= 2 ? c - i0 : 0.0};
}

AxisSample axis_sample(const Grid3& grid, int a, double coord) {
  return index_sample(grid.dims[a], (coord - grid.origin[a]) / grid.cell);
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

// Level l's lookups at every base coordinate k of axis a: the level coordinate k / 2^l (exact),
// clamped into the level.
std::vector<AxisLookup> axis_table(const Grid3& level, unsigned base_n, unsigned shift, int a) {
  const std::size_t stride = a == 0 ? 1 : (a == 1 ? level.dims.x : std::size_t(level.dims.x) * level.dims.y);
  std::vector<AxisLookup> out(base_n);
  for (unsigned k = 0; k < base_n; ++k)
    out[k] = axis_lookup(index_sample(level.dims[a], std::ldexp(double(k), -int(shift))), stride);
  return out;
}

// The index-space sampling below holds only for levels laid out as the pyramid builds them.
void check_levels(const std::vector<Grid3>& pyramid) {
  const Grid3& base = pyramid.front();
  const std::vector<glm::uvec3> dims = pyramid_level_dims(base.dims, int(pyramid.size()));
  for (std::size_t l = 0; l < pyramid.size(); ++l) {
    const Grid3& level = pyramid[l];
    if (level.dims != dims[l] || level.origin != base.origin || level.cell != std::ldexp(base.cell, int(l)) ||
        level.values.size() != level.size())
      throw InputError("field gradient: pyramid level " + std::to_string(l) +
                       " is not the base grid coarsened 2^" + std::to_string(l) + "-fold (dims, origin or cell differ)");
  }
}

// ψ_l at every base node: level l trilinear at the node's level coordinates.
std::vector<double> level_at_base_nodes(const Grid3& level, const Grid3& base, unsigned shift) {
  const std::vector<AxisLookup> tx = axis_table(level, base.dims.x, shift, 0), ty = axis_table(level, base.dims.y, shift, 1),
                                tz = axis_table(level, base.dims.z, shift, 2);
  std::vector<double> out(base.size());
  const float* v = level.values.data();
  const std::size_t rows = std::size_t(base.dims.y) * base.dims.z;
  parallel_chunks(rows, chunk_count(rows, 64), 2, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r) {
      const std::size_t y = r % base.dims.y, z = r / base.dims.y;
      double* row = out.data() + r * base.dims.x;
      for (unsigned x = 0; x < base.dims.x; ++x) row[x] = trilinear(v, tx[x], ty[y], tz[z]);
    }
  });
  return out;
}

}  // namespace

double sample_trilinear(const Grid3& grid, const glm::dvec3& p) {
  return trilinear(grid, axis_sample(grid, 0, p.x), axis_sample(grid, 1, p.y), axis_sample(grid, 2, p.z));
}

// Level l's cell is 2^l base cells and its origin the base's, so base node k sits at level
// coordinate k / 2^l: each level is interpolated once per base node.
FieldGrid4 precompute_field_gradient(const std::vector<Grid3>& pyramid) {
  if (pyramid.empty()) throw InputError("field gradient: the pyramid has no levels");
  check_levels(pyramid);
  const Grid3& base = pyramid.front();
  FieldGrid4 out{base.dims, base.origin, base.cell, std::vector<glm::vec4>(base.size())};
  const glm::ivec3 n(base.dims);
  const std::size_t rows = std::size_t(base.dims.y) * base.dims.z;
  // ψ̃ at the base nodes first (the levels summed in order, one at a time); then its central
  // differences, one base cell either side (one-sided at the grid's faces): the gradient of what
  // the refiner samples, so its flow descends the energy it measures (see the header).
  std::vector<double> value(base.size(), 0.0);
  for (std::size_t l = 0; l < pyramid.size(); ++l) {
    const std::vector<double> level = level_at_base_nodes(pyramid[l], base, unsigned(l));
    for (std::size_t i = 0; i < value.size(); ++i) value[i] += level[i];
  }
  for (double& v : value) v /= double(pyramid.size());
  parallel_chunks(rows, chunk_count(rows, 64), 2, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r) {
      const int y = int(r % base.dims.y), z = int(r / base.dims.y);
      for (int x = 0; x < n.x; ++x) {
        const glm::ivec3 at(x, y, z);
        glm::dvec3 grad(0.0);
        for (int a = 0; a < 3; ++a) {
          glm::ivec3 lo = at, hi = at;
          lo[a] = std::max(at[a] - 1, 0), hi[a] = std::min(at[a] + 1, n[a] - 1);
          if (hi[a] == lo[a]) continue;
          const double dv = value[base.index(unsigned(hi.x), unsigned(hi.y), unsigned(hi.z))] -
                            value[base.index(unsigned(lo.x), unsigned(lo.y), unsigned(lo.z))];
          grad[a] = dv / (double(hi[a] - lo[a]) * base.cell);
        }
        const std::size_t i = base.index(unsigned(x), unsigned(y), unsigned(z));
        out.values[i] = glm::vec4(float(value[i]), glm::vec3(grad));
      }
    }
  });
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
