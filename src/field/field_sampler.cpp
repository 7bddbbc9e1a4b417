#include "field/field_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

namespace fracref {
namespace {

double clamp_coord(double g, unsigned n) { return std::clamp(g, 0.0, double(n > 0 ? n - 1 : 0)); }

}  // namespace

double sample_trilinear(const Grid3& grid, const glm::dvec3& p) {
  glm::dvec3 g = (p - grid.origin) / grid.cell;
  unsigned idx[3][2];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    unsigned n = grid.dims[a];
    double c = clamp_coord(g[a], n);
    unsigned i0 = n >= 2 ? std::min<unsigned>(unsigned(std::floor(c)), n - 2) : 0;
    idx[a][0] = i0;
    idx[a][1] = n >= 2 ? i0 + 1 : 0;
    t[a] = n >= 2 ? c - i0 : 0.0;
  }
  double acc = 0.0;
  for (int k = 0; k < 8; ++k) {
    int bx = k & 1, by = (k >> 1) & 1, bz = (k >> 2) & 1;
    double w = (bx ? t[0] : 1 - t[0]) * (by ? t[1] : 1 - t[1]) * (bz ? t[2] : 1 - t[2]);
    acc += w * grid.at(idx[0][bx], idx[1][by], idx[2][bz]);
  }
  return acc;
}

FieldGrid4 precompute_field_gradient(const std::vector<Grid3>& pyramid) {
  const Grid3& base = pyramid.front();
  FieldGrid4 out{base.dims, base.origin, base.cell, std::vector<glm::vec4>(base.size())};
  const double levels = double(pyramid.size());
  auto slab = [&](unsigned z0, unsigned z1) {
    for (unsigned z = z0; z < z1; ++z)
      for (unsigned y = 0; y < base.dims.y; ++y)
        for (unsigned x = 0; x < base.dims.x; ++x) {
          glm::dvec3 p = base.node_position(x, y, z);
          glm::dvec3 grad(0.0);
          double value = 0.0;
          for (const Grid3& level : pyramid) {
            double h = level.cell;
            value += sample_trilinear(level, p);
            for (int a = 0; a < 3; ++a) {
              glm::dvec3 e(0.0);
              e[a] = h;
              grad[a] += (sample_trilinear(level, p + e) - sample_trilinear(level, p - e)) / (2.0 * h);
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
