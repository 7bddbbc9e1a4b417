#include "pipeline/quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "geom/bvh.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {

glm::dvec3 at(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }

struct AreaSums {
  double area = 0.0, energy = 0.0, weak = 0.0;
};

// Face f cut into n² triangles (n per side, n = ⌈longest edge / cell⌉, at most `most`), fn(point,
// area) at each one's centroid.
template <class Fn>
void for_each_sample(const FractureSurface& s, std::uint32_t f, double cell, Fn fn, int most = 256) {
  const glm::uvec4 t = s.faces[f];
  const glm::dvec3 a = at(s, t.x), b = at(s, t.y), c = at(s, t.z);
  const double longest = std::max({glm::distance(a, b), glm::distance(b, c), glm::distance(c, a)});
  const int n = std::clamp(int(std::ceil(longest / cell)), 1, most);
  const double sub = 0.5 * glm::length(glm::cross(b - a, c - a)) / double(n * n);
  const glm::dvec3 u = (b - a) / double(n), v = (c - a) / double(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      const glm::dvec3 o = a + double(i) * u + double(j) * v;
      fn(o + (u + v) / 3.0, sub);                                 // the upright sub-triangle
      if (i + j + 1 < n) fn(o + (2.0 * u + 2.0 * v) / 3.0, sub);  // the inverted one beside it
    }
}

AreaSums face_sums(const FractureSurface& s, std::uint32_t f, const FieldGrid4& field, const Grid3& zeta,
                   double threshold) {
  AreaSums out;
  for_each_sample(s, f, zeta.cell, [&](const glm::dvec3& p, double sub) {
    out.area += sub;
    out.energy += sub * double(sample_field(field, glm::vec3(p)).x);
    if (sample_trilinear(zeta, p) < threshold) out.weak += sub;
  });
  return out;
}

AreaSums surface_sums(const FractureSurface& s, const FieldGrid4& field, const Grid3& zeta, double threshold) {
  const std::size_t chunks = chunk_count(s.faces.size(), 1024);
  std::vector<AreaSums> part(chunks);
  parallel_chunks(s.faces.size(), chunks, 2, [&](std::size_t c, std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const AreaSums a = face_sums(s, std::uint32_t(f), field, zeta, threshold);
      part[c].area += a.area, part[c].energy += a.energy, part[c].weak += a.weak;
    }
  });
  AreaSums sum;
  for (const AreaSums& p : part) sum.area += p.area, sum.energy += p.energy, sum.weak += p.weak;
  return sum;
}

double weak_threshold(const Grid3& zeta, const ExteriorSurface& b) {
  std::vector<float> inside;
  for (unsigned z = 0; z < zeta.dims.z; ++z)
    for (unsigned y = 0; y < zeta.dims.y; ++y)
      for (unsigned x = 0; x < zeta.dims.x; ++x)
        if (b.contains(zeta.node_position(x, y, z))) inside.push_back(zeta.at(x, y, z));
  if (inside.empty()) return 0.0;
  auto q = inside.begin() + inside.size() / 4;
  std::nth_element(inside.begin(), q, inside.end());
  return double(*q);
}

void displacement(const FractureSurface& coarse, const FractureSurface& refined, double diagonal, SurfaceQuality& q) {
  std::vector<glm::dvec3> pos;
  for (std::uint32_t v = 0; v < coarse.positions.size(); ++v) pos.push_back(at(coarse, v));
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (const glm::uvec4& f : coarse.faces) tris.push_back({f.x, f.y, f.z});
  const Bvh bvh = build_bvh(pos, tris);
  std::vector<std::pair<double, double>> dist_weight(refined.positions.size(), {0.0, 0.0});
  for (std::uint32_t v = 0; v < refined.positions.size(); ++v)
    dist_weight[v].first = std::sqrt(closest_point(bvh, at(refined, v)).squared_distance) / diagonal;
  double total = 0.0;
  for (const glm::uvec4& f : refined.faces) {
    const double w = glm::length(glm::cross(at(refined, f.y) - at(refined, f.x), at(refined, f.z) - at(refined, f.x))) / 6.0;
    for (int c = 0; c < 3; ++c) dist_weight[f[c]].second += w;
    total += 3.0 * w;
  }
  double mean = 0.0;
  // A vertex with no face (a hairpin tip collapsed: refine/collapses.hpp) is not on S.
  for (const auto& [d, w] : dist_weight)
    if (w > 0.0) mean += d * w, q.displacement_max = std::max(q.displacement_max, d);
  q.displacement_mean = total > 0.0 ? mean / total : 0.0;
  std::sort(dist_weight.begin(), dist_weight.end());
  double acc = 0.0;
  for (const auto& [d, w] : dist_weight) {
    acc += w;
    q.displacement_p95 = d;
    if (acc >= 0.95 * total) break;
  }
}

// Face f's samples as (distance to weak material along the normal, area); +inf where none is
// within `limit`.
void face_reach(const FractureSurface& s, std::uint32_t f, const Grid3& zeta, double threshold, double limit,
                std::vector<std::pair<double, double>>& out) {
  const glm::uvec4 t = s.faces[f];
  const glm::dvec3 cross = glm::cross(at(s, t.y) - at(s, t.x), at(s, t.z) - at(s, t.x));
  const double length = glm::length(cross);
  if (!(length > 0.0)) return;
  const glm::dvec3 normal = cross / length;
  // Half a cell, but no more than 128 steps either way and 16² samples a face: on a fine grid
  // the search costs samples × steps lookups.
  const double step = std::max(0.5 * zeta.cell, limit / 128.0);
  const int steps = int(std::floor(limit / step));
  for_each_sample(s, f, zeta.cell, [&](const glm::dvec3& p, double sub) {
    double d = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= steps && !std::isfinite(d); ++k)
      if (sample_trilinear(zeta, p + double(k) * step * normal) < threshold ||
          sample_trilinear(zeta, p - double(k) * step * normal) < threshold)
        d = double(k) * step;
    out.emplace_back(d, sub);
  }, 16);
}

}  // namespace

WeakReach weak_reach(const FractureSurface& s, const Grid3& zeta, double threshold, double radius, double diagonal,
                     double max_radius) {
  const std::size_t chunks = chunk_count(s.faces.size(), 256);
  std::vector<std::vector<std::pair<double, double>>> part(chunks);
  parallel_chunks(s.faces.size(), chunks, default_threads(), [&](std::size_t c, std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) face_reach(s, std::uint32_t(f), zeta, threshold, max_radius * diagonal, part[c]);
  });
  std::vector<std::pair<double, double>> all;
  for (const auto& p : part) all.insert(all.end(), p.begin(), p.end());
  std::sort(all.begin(), all.end());
  double total = 0.0, within = 0.0;
  for (const auto& [d, w] : all) total += w, within += d <= radius * diagonal ? w : 0.0;
  WeakReach out{total > 0.0 ? within / total : 0.0, std::numeric_limits<double>::infinity()};
  double acc = 0.0;
  for (const auto& [d, w] : all)
    if ((acc += w) >= 0.5 * total) {
      out.half_radius = d / diagonal;
      break;
    }
  return out;
}

SurfaceQuality measure_quality(const FractureSurface& coarse, const FractureSurface& refined, const FieldGrid4& field,
                               const Grid3& zeta, const ExteriorSurface& exterior) {
  SurfaceQuality q;
  q.weak_threshold = weak_threshold(zeta, exterior);
  const AreaSums c = surface_sums(coarse, field, zeta, q.weak_threshold);
  const AreaSums r = surface_sums(refined, field, zeta, q.weak_threshold);
  q.coarse_energy = c.energy, q.refined_energy = r.energy;
  q.energy_ratio = c.energy > 0.0 ? r.energy / c.energy : 0.0;
  q.weak_coarse = c.area > 0.0 ? c.weak / c.area : 0.0;
  q.weak_refined = r.area > 0.0 ? r.weak / r.area : 0.0;
  displacement(coarse, refined, exterior.diagonal(), q);
  const WeakReach reach = weak_reach(coarse, zeta, q.weak_threshold, q.displacement_p95, exterior.diagonal());
  q.weak_reachable = reach.fraction, q.weak_half_radius = reach.half_radius;
  return q;
}

}  // namespace fracref
