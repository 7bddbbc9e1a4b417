// Re-triangulation of a fracture face whose sides carry trace points. A triangle with all three
// corners on one side would lie along B (a sliver folded onto the exterior), so none is made:
// with one cut side the result is the fan from the opposite corner; with more, ear clipping in
// the face's plane takes the best-shaped allowed ear first.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "geom/predicates.hpp"
#include "pieces/pieces_internal.hpp"
#include "util/error.hpp"

namespace fracref::pieces_detail {
namespace {

using Tri = std::array<std::uint32_t, 3>;

// The barycentric grid searched for a face centre when the centroid does not see every side.
constexpr int kCentreGrid = 12;

double min_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  auto angle = [](const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
    const glm::dvec3 u = q - p, v = r - p;
    return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
  };
  return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

class EarClipper {
 public:
  EarClipper(const std::vector<glm::dvec3>& polygon, const std::vector<unsigned>& mask, const glm::dvec3& normal,
             const FlatTest& flat)
      : xyz_(polygon), mask_(mask), flat_(flat) {
    const glm::dvec3 n = glm::normalize(normal);
    const glm::dvec3 a = std::abs(n.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    e1_ = glm::normalize(glm::cross(n, a));
    e2_ = glm::cross(n, e1_);
    for (const glm::dvec3& p : polygon) uv_.push_back(project(p));
  }

  std::vector<Tri> fan(std::uint32_t apex) {
    std::vector<Tri> out;
    const std::uint32_t n = std::uint32_t(xyz_.size());
    for (std::uint32_t i = 1; i + 1 < n; ++i) {
      const Tri t{apex, (apex + i) % n, (apex + i + 1) % n};
      if (orient(t[0], t[1], t[2]) <= 0) throw RunError("the traced boundary is not visible from the opposite corner");
      if (flat(t[0], t[1], t[2])) throw RunError("a triangle of the fan would lie flat on the exterior");
      out.push_back(t);
    }
    return out;
  }

  // Every side of the polygon joined to a point inside it (index xyz_.size()).
  std::vector<Tri> centre_fan(const glm::dvec3& centre) {
    const std::uint32_t n = std::uint32_t(xyz_.size());
    uv_.resize(n);
    uv_.push_back(project(centre));
    std::vector<Tri> out;
    for (std::uint32_t i = 0; i < n; ++i) {
      const Tri t{i, (i + 1) % n, n};
      if (orient(t[0], t[1], t[2]) <= 0) throw RunError("the traced boundary is not visible from the face's centre");
      out.push_back(t);
    }
    return out;
  }

  // The smallest distance from the projection of x to the lines of the polygon's sides,
  // negative when x lies to the right of one (does not see it).
  double clearance(const glm::dvec3& x) const {
    const glm::dvec2 c = project(x);
    double least = std::numeric_limits<double>::infinity();
    const std::size_t n = xyz_.size();
    for (std::size_t i = 0; i < n; ++i) {
      const glm::dvec2 a = uv_[i], d = uv_[(i + 1) % n] - a;
      const double len = glm::length(d);
      if (len > 0.0) least = std::min(least, (d.x * (c.y - a.y) - d.y * (c.x - a.x)) / len);
    }
    return least;
  }

  std::vector<Tri> clip() {
    std::vector<std::uint32_t> ring(xyz_.size());
    for (std::uint32_t i = 0; i < ring.size(); ++i) ring[i] = i;
    std::vector<Tri> out;
    while (ring.size() > 3) {
      std::size_t best = ring.size();
      double best_score = -1.0;
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const std::uint32_t u = ring[(i + ring.size() - 1) % ring.size()], v = ring[i], w = ring[(i + 1) % ring.size()];
        if (!is_ear(ring, u, v, w)) continue;
        const double score = min_angle(xyz_[u], xyz_[v], xyz_[w]);
        if (score > best_score) best_score = score, best = i;
      }
      if (best == ring.size()) throw RunError("no valid ear is left while re-triangulating it");
      out.push_back({ring[(best + ring.size() - 1) % ring.size()], ring[best], ring[(best + 1) % ring.size()]});
      ring.erase(ring.begin() + std::ptrdiff_t(best));
    }
    if ((mask_[ring[0]] & mask_[ring[1]] & mask_[ring[2]] & 7u) != 0 || flat(ring[0], ring[1], ring[2]) ||
        orient(ring[0], ring[1], ring[2]) <= 0)
      throw RunError("its last triangle would be degenerate");
    out.push_back({ring[0], ring[1], ring[2]});
    return out;
  }

 private:
  glm::dvec2 project(const glm::dvec3& p) const { return {glm::dot(p - xyz_[0], e1_), glm::dot(p - xyz_[0], e2_)}; }
  int orient(std::uint32_t a, std::uint32_t b, std::uint32_t c) const { return orient2d(uv_[a], uv_[b], uv_[c]); }
  bool flat(std::uint32_t u, std::uint32_t v, std::uint32_t w) const {
    return flat_ && (mask_[u] & mask_[v] & mask_[w] & kOnExterior) != 0 && flat_(xyz_[u], xyz_[v], xyz_[w]);
  }

  // An ear (u, v, w) must be strictly convex, empty, not flat on B, and its diagonal (u, w) must
  // not join two points of one side: the part it cuts off would be a chain of that side only.
  bool is_ear(const std::vector<std::uint32_t>& ring, std::uint32_t u, std::uint32_t v, std::uint32_t w) const {
    if ((mask_[u] & mask_[w] & 7u) != 0 || orient(u, v, w) <= 0 || flat(u, v, w)) return false;
    for (std::uint32_t z : ring) {
      if (z == u || z == v || z == w) continue;
      if (orient(u, v, z) >= 0 && orient(v, w, z) >= 0 && orient(w, u, z) >= 0) return false;
    }
    return true;
  }

  const std::vector<glm::dvec3>& xyz_;
  const std::vector<unsigned>& mask_;
  const FlatTest& flat_;
  glm::dvec3 e1_{0.0}, e2_{0.0};
  std::vector<glm::dvec2> uv_;
};

}  // namespace

FracturePolygon triangulate_fracture_polygon(const std::vector<glm::dvec3>& polygon, const std::vector<unsigned>& side_mask,
                                             const glm::dvec3& normal, const FlatTest& flat) {
  FracturePolygon out;
  if (polygon.size() == 3) {
    out.triangles = {{0, 1, 2}};
    return out;
  }
  // The polygon follows B and is not planar: project along its vector area (Newell's normal),
  // which sees a path bending around a crease of B better than the plane of the corners does.
  glm::dvec3 area(0.0);
  for (std::size_t i = 0; i < polygon.size(); ++i) area += glm::cross(polygon[i], polygon[(i + 1) % polygon.size()]);
  if (normal != glm::dvec3(0.0) && !(glm::dot(area, normal) > 0.0)) throw RunError("the traced boundary folds over the face");
  EarClipper clipper(polygon, side_mask, area, flat);
  try {
    // One cut side: the fan from the corner off that side is the only allowed triangulation.
    unsigned cut_sides = 0;
    for (unsigned m : side_mask)
      if ((m & 7u) == 1u || (m & 7u) == 2u || (m & 7u) == 4u) cut_sides |= m & 7u;
    if (cut_sides == 1u || cut_sides == 2u || cut_sides == 4u) {
      for (std::uint32_t i = 0; i < polygon.size(); ++i)
        if ((side_mask[i] & cut_sides) == 0) {
          out.triangles = clipper.fan(i);
          return out;
        }
    }
    out.triangles = clipper.clip();
    return out;
  } catch (const RunError& by_sides) {
    // A face with all corners on B whose traces bend over a crease: no triangle among its own
    // points avoids lying flat on B, so every side is joined to a point of the face's triangle:
    // its centroid, or else the point of a barycentric grid that sees every side best (a
    // needle-thin face whose traces bend toward its centroid).
    std::array<std::size_t, 3> corner{};
    int corners = 0;
    for (std::size_t i = 0; i < polygon.size() && corners <= 3; ++i)
      if (std::popcount(side_mask[i] & 7u) == 2) {
        if (corners < 3) corner[std::size_t(corners)] = i;
        ++corners;
      }
    if (corners != 3) throw;
    auto at = [&](const glm::dvec3& w) { return w.x * polygon[corner[0]] + w.y * polygon[corner[1]] + w.z * polygon[corner[2]]; };
    glm::dvec3 weights(1.0 / 3.0);
    if (!(clipper.clearance(at(weights)) > 0.0)) {
      double best = 0.0;
      for (int i = 1; i < kCentreGrid; ++i)
        for (int j = 1; i + j < kCentreGrid; ++j) {
          const glm::dvec3 w(double(i) / kCentreGrid, double(j) / kCentreGrid, double(kCentreGrid - i - j) / kCentreGrid);
          const double c = clipper.clearance(at(w));
          if (c > best) best = c, weights = w;
        }
    }
    try {
      out.centre = weights == glm::dvec3(1.0 / 3.0) ? (polygon[corner[0]] + polygon[corner[1]] + polygon[corner[2]]) / 3.0 : at(weights);
      out.centre_weights = weights;
      out.triangles = clipper.centre_fan(out.centre);
      out.centre_added = true;
      return out;
    } catch (const RunError&) {
      throw by_sides;
    }
  }
}

}  // namespace fracref::pieces_detail
