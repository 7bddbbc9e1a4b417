// A structured tet mesh of a capped cylinder: a disc of rings extruded into prisms.
#include <cmath>
#include <numbers>
#include <utility>

#include "scenegen/scenegen_internal.hpp"
#include "util/error.hpp"

namespace fracref::scenegen_detail {
namespace {

struct Disc {
  std::vector<glm::dvec2> points;
  std::vector<glm::uvec3> triangles;
};

// Rings at evenly spaced radii; the outer ring at every other vertex of a `2 n`-gon, computed as
// make_cylinder computes its vertices.
Disc ring_disc(double radius, const std::vector<int>& counts) {
  Disc d;
  std::vector<std::uint32_t> start;
  const int rings = int(counts.size()), segments = 2 * counts.back();
  for (int i = 0; i < rings; ++i) {
    start.push_back(std::uint32_t(d.points.size()));
    if (counts[i] == 1) {
      d.points.push_back({0.0, 0.0});
      continue;
    }
    const double r = radius * double(i) / double(rings - 1);
    for (int k = 0; k < counts[i]; ++k) {
      if (i == rings - 1) {
        const double a = 2.0 * std::numbers::pi * double(2 * k) / double(segments);
        d.points.push_back({radius * std::cos(a), radius * std::sin(a)});
      } else {
        const double a = 2.0 * std::numbers::pi * double(k) / double(counts[i]);
        d.points.push_back({r * std::cos(a), r * std::sin(a)});
      }
    }
  }
  for (int i = 0; i + 1 < rings; ++i) {
    const int na = counts[i], nb = counts[i + 1];
    const auto A = [&](int k) { return start[i] + std::uint32_t(k % na); };
    const auto B = [&](int k) { return start[i + 1] + std::uint32_t(k % nb); };
    // Walk both rings by angle, always stepping on the ring whose next vertex comes first.
    for (int a = 0, b = 0; a < na || b < nb;) {
      const bool step_a = na > 1 && (b == nb || (a < na && double(a + 1) / na <= double(b + 1) / nb));
      if (step_a) d.triangles.push_back({A(a), B(b), A(a + 1)}), ++a;
      else d.triangles.push_back({A(a), B(b), B(b + 1)}), ++b;
      if (na == 1) a = 1;
    }
  }
  return d;
}

}  // namespace

TetSet cylinder_tets(double radius, double length, const std::vector<int>& ring_counts, int layers) {
  if (ring_counts.size() < 2 || ring_counts.front() != 1 || layers < 1)
    throw RunError("scenegen: a cylinder needs a centre, one ring or more, and a layer");
  const Disc disc = ring_disc(radius, ring_counts);
  const std::uint32_t n = std::uint32_t(disc.points.size());
  TetSet set;
  for (int l = 0; l <= layers; ++l) {
    const double z = -0.5 * length + length * double(l) / double(layers);
    for (const glm::dvec2& p : disc.points) set.positions.push_back({p.x, p.y, z});
  }
  // Each quad between disc vertices i < j is cut from i below to j above, in every prism that
  // has it, so the prisms' tets conform.
  for (int l = 0; l < layers; ++l)
    for (glm::uvec3 t : disc.triangles) {
      if (t.x > t.y) std::swap(t.x, t.y);
      if (t.y > t.z) std::swap(t.y, t.z);
      if (t.x > t.y) std::swap(t.x, t.y);
      const std::uint32_t a = t.x + l * n, b = t.y + l * n, c = t.z + l * n;
      for (glm::uvec4 tet : {glm::uvec4(a, b, c, c + n), glm::uvec4(a, b, b + n, c + n), glm::uvec4(a, a + n, b + n, c + n)}) {
        set.tets.push_back(tet);
        if (tet_volume(set, std::uint32_t(set.tets.size() - 1)) < 0.0) std::swap(set.tets.back().z, set.tets.back().w);
      }
    }
  return set;
}

}  // namespace fracref::scenegen_detail
