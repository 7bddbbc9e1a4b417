#include "geom/quad_prism.hpp"

#include <algorithm>
#include <cmath>

namespace fracref {
namespace {

double max_abs(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

}  // namespace

// Each plane is n . x = level for a computed unit n and level: a true plane, whatever rounding
// went into them. The corners are taken to lie behind it when their computed n . x - level is at
// most half a margin, and a point of g beyond it when that passes a whole margin; the margins
// (1e-9 of the sizes and coordinates involved) dwarf the rounding of these dot products (~1e-15
// of them). A plane through a shared corner is placed at that corner exactly (n . (x - corner)).
QuadPrism::QuadPrism(const std::array<glm::dvec3, 4>& p, const glm::dvec3& normal, double grow) : p_(p), grow_(grow) {
  normal_ = glm::normalize(normal);
  glm::dvec3 lo = p[0], hi = p[0];
  for (const glm::dvec3& v : p) lo = glm::min(lo, v), hi = glm::max(hi, v);
  size_ = max_abs(hi - lo);
  scale_ = std::max(max_abs(lo), max_abs(hi));
  top_ = bottom_ = glm::dot(normal_, p[0]);
  for (const glm::dvec3& v : p) {
    const double h = glm::dot(normal_, v);
    bottom_ = std::min(bottom_, h), top_ = std::max(top_, h);
  }
  const double behind = 0.5e-9 * (size_ + scale_);
  for (int k = 0; k < 4; ++k) {
    Side& s = sides_[k];
    const glm::dvec3 n = glm::cross(p[(k + 1) % 4] - p[k], normal_);
    const double length = glm::length(n);
    s.normal = length > 0.0 ? n / length : glm::dvec3(0.0);
    // Oriented away from the other two corners, then kept only where all four lie behind it.
    if (glm::dot(s.normal, p[(k + 2) % 4] - p[k]) + glm::dot(s.normal, p[(k + 3) % 4] - p[k]) > 0.0) s.normal = -s.normal;
    s.level = glm::dot(s.normal, p[k]);
    for (int e = 0; e < 2; ++e) {
      const glm::dvec3& origin = p[(k + e) % 4];
      s.from[e] = length > 0.0;
      for (const glm::dvec3& v : p)
        s.from[e] = s.from[e] && glm::dot(s.normal, v - origin) <= behind && glm::dot(s.normal, v) - s.level <= behind;
    }
  }
}

bool QuadPrism::separates(const std::array<glm::dvec3, 3>& g, const std::array<int, 3>& shared) const {
  const int n_shared = int(shared[0] >= 0) + int(shared[1] >= 0) + int(shared[2] >= 0);
  if (n_shared >= 2 || (n_shared == 1 && grow_ > 0.0)) return false;
  // The grown planes: each moved out by grow_ (its margin covers the rounding of that sum too).
  const double margin = grow_ + 1e-9 * (grow_ + size_ + scale_ + std::max({max_abs(g[0]), max_abs(g[1]), max_abs(g[2])}));
  if (n_shared == 1) {
    const int c = shared[0] >= 0 ? shared[0] : (shared[1] >= 0 ? shared[1] : shared[2]);
    auto all_beyond = [&](const glm::dvec3& n) {
      for (int k = 0; k < 3; ++k)
        if (shared[k] < 0 && !(glm::dot(n, g[k] - p_[c]) > margin)) return false;
      return true;
    };
    // The sides at corner c: (c-1, c) placed at its second corner, (c, c+1) at its first.
    const Side& before = sides_[(c + 3) % 4];
    return (before.from[1] && all_beyond(before.normal)) || (sides_[c].from[0] && all_beyond(sides_[c].normal));
  }
  const double h[3] = {glm::dot(normal_, g[0]), glm::dot(normal_, g[1]), glm::dot(normal_, g[2])};
  if (h[0] - top_ > margin && h[1] - top_ > margin && h[2] - top_ > margin) return true;
  if (bottom_ - h[0] > margin && bottom_ - h[1] > margin && bottom_ - h[2] > margin) return true;
  for (const Side& s : sides_) {
    if (!s.from[0]) continue;
    if (glm::dot(s.normal, g[0]) - s.level > margin && glm::dot(s.normal, g[1]) - s.level > margin &&
        glm::dot(s.normal, g[2]) - s.level > margin)
      return true;
  }
  return false;
}

// The least and the greatest n . x over the box are taken corner by corner (rounded a few ulps,
// far below the margin), so the whole box lies beyond a plane exactly when they pass it.
bool QuadPrism::separates_box(const glm::dvec3& lo, const glm::dvec3& hi) const {
  const double margin = grow_ + 1e-9 * (grow_ + size_ + scale_ + std::max(max_abs(lo), max_abs(hi)));
  auto least = [&](const glm::dvec3& n) {
    return (n.x >= 0.0 ? n.x * lo.x : n.x * hi.x) + (n.y >= 0.0 ? n.y * lo.y : n.y * hi.y) +
           (n.z >= 0.0 ? n.z * lo.z : n.z * hi.z);
  };
  if (least(normal_) - top_ > margin || bottom_ + least(-normal_) > margin) return true;
  for (const Side& s : sides_)
    if (s.from[0] && least(s.normal) - s.level > margin) return true;
  return false;
}

}  // namespace fracref
