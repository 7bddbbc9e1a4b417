#include "refine/step_guard.hpp"

#include <algorithm>
#include <cmath>

#include "surface/radial_order.hpp"

namespace fracref {
namespace {

glm::dvec3 at(const std::vector<glm::vec4>& x, std::uint32_t v) { return glm::dvec3(glm::vec3(x[v])); }

bool folds(const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1, const glm::uvec4& f, double ratio) {
  const glm::dvec3 n0 = glm::cross(at(x0, f.y) - at(x0, f.x), at(x0, f.z) - at(x0, f.x));
  const glm::dvec3 n1 = glm::cross(at(x1, f.y) - at(x1, f.x), at(x1, f.z) - at(x1, f.x));
  return !(glm::dot(n0, n1) > ratio * glm::dot(n0, n0));
}

// Whether the motion turns face f, which meets B where its normal is nb, closer to B's tangent
// plane than the limit (and closer than it was).
bool lies_down(const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1, const glm::uvec4& f,
               const glm::dvec3& nb, double max_cos) {
  auto cos_to_b = [&](const std::vector<glm::vec4>& x) {
    const glm::dvec3 n = glm::cross(at(x, f.y) - at(x, f.x), at(x, f.z) - at(x, f.x));
    const double len = glm::length(n);
    return len > 0.0 ? std::abs(glm::dot(n, nb)) / len : 1.0;
  };
  const double c1 = cos_to_b(x1);
  return c1 > max_cos && c1 > cos_to_b(x0);
}

// The faces of edge e in their order around it at positions x (the order rebuild_adjacency
// reads), written from the lowest face id: two positions give the same sequence when no face
// passed another.
std::vector<std::uint32_t> cyclic_order(const FractureSurface& s, std::uint32_t e, const std::vector<glm::vec4>& x) {
  const glm::uvec2 ab = s.edges[e];
  return from_lowest(radial_order_about(s, e, at(x, ab.x), at(x, ab.y), [&](std::uint32_t f) {
    const glm::uvec4 t = s.faces[f];
    return at(x, t.x + t.y + t.z - ab.x - ab.y);
  }));
}

std::size_t hold(const glm::uvec4& f, const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1) {
  std::size_t n = 0;
  for (int c = 0; c < 3; ++c)
    if (x1[f[c]] != x0[f[c]]) x1[f[c]] = x0[f[c]], ++n;
  return n;
}

bool moves(const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1, const glm::uvec4& f) {
  return x1[f.x] != x0[f.x] || x1[f.y] != x0[f.y] || x1[f.z] != x0[f.z];
}

// One pass over the faces and the junction edges of the motion x0 → x1; with `reset` (which is
// x1) the offending vertices are reset, otherwise the pass stops at the first offence. Returns
// the vertices reset (or 1 for an offence).
std::size_t guard_pass(const FractureSurface& s, const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1,
                       const StepGuardOptions& o, std::vector<glm::vec4>* reset) {
  std::size_t held = 0;
  const double max_cos = std::cos(o.min_rim_angle * 3.14159265358979323846 / 180.0);
  for (std::size_t j = 0; j < s.faces.size(); ++j) {
    const glm::uvec4 f = s.faces[j];
    if (!moves(x0, x1, f)) continue;
    const bool rim = j < o.rim_normals.size() && o.rim_normals[j] != glm::dvec3(0.0);
    if (!folds(x0, x1, f, o.min_area_ratio) && !(rim && lies_down(x0, x1, f, o.rim_normals[j], max_cos))) continue;
    if (!reset) return 1;
    held += hold(f, x0, *reset);
  }
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    if (s.edge_special[e] != kEdgeNonManifold) continue;
    const std::uint32_t* first = s.ef_faces.data() + s.ef_offsets[e];
    const std::uint32_t* last = s.ef_faces.data() + s.ef_offsets[e + 1];
    if (std::none_of(first, last, [&](std::uint32_t f) { return moves(x0, x1, s.faces[f]); })) continue;
    if (cyclic_order(s, e, x0) == cyclic_order(s, e, x1)) continue;
    if (!reset) return 1;
    for (const std::uint32_t* f = first; f != last; ++f) held += hold(s.faces[*f], x0, *reset);
  }
  return held;
}

}  // namespace

std::size_t hold_folding_motion(const FractureSurface& s, const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1,
                                const StepGuardOptions& o) {
  std::size_t held = 0;
  while (const std::size_t now = guard_pass(s, x0, x1, o, &x1)) held += now;
  return held;
}

bool motion_folds(const FractureSurface& s, const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1,
                  const StepGuardOptions& o) {
  return guard_pass(s, x0, x1, o, nullptr) != 0;
}

}  // namespace fracref
