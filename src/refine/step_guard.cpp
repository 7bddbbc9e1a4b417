#include "refine/step_guard.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "geom/intersect.hpp"
#include "util/parallel.hpp"
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

// Whether a plane through v clearly separates faces f and g (which share only v), so that they
// meet only at v: the plane of one face with both other corners of the other on one side, or the
// plane through an edge of one face at v, square to that face, with its third corner on one side
// and both other corners of the other face on the other side (a fan flat as a plane is told apart
// by those). Floating point with a margin far above its rounding; the undecided go to the exact
// test.
bool clearly_apart(const std::vector<glm::vec4>& x, std::uint32_t v, const glm::uvec4& f, const glm::uvec4& g) {
  const glm::dvec3 o = at(x, v);
  glm::dvec3 p[2], q[2];
  for (int c = 0, i = 0, j = 0; c < 3; ++c) {
    if (f[c] != v) p[i++] = at(x, f[c]) - o;
    if (g[c] != v) q[j++] = at(x, g[c]) - o;
  }
  const double scale = std::max({glm::length(p[0]), glm::length(p[1]), glm::length(q[0]), glm::length(q[1])});
  // +1 / −1 when both points are clearly on that side of the plane through v with normal m, else 0.
  auto side = [&](const glm::dvec3& m, const glm::dvec3& a, const glm::dvec3& b) {
    const double margin = 1e-9 * glm::length(m) * scale, da = glm::dot(m, a), db = glm::dot(m, b);
    return da > margin && db > margin ? 1 : da < -margin && db < -margin ? -1 : 0;
  };
  const glm::dvec3 nf = glm::cross(p[0], p[1]), ng = glm::cross(q[0], q[1]);
  if (side(nf, q[0], q[1]) != 0 || side(ng, p[0], p[1]) != 0) return true;
  for (int k = 0; k < 2; ++k) {
    const glm::dvec3 mf = glm::cross(nf, p[k]), mg = glm::cross(ng, q[k]);
    const int own_f = side(mf, p[1 - k], p[1 - k]), own_g = side(mg, q[1 - k], q[1 - k]);
    if (own_f != 0 && side(mf, q[0], q[1]) == -own_f) return true;
    if (own_g != 0 && side(mg, p[0], p[1]) == -own_g) return true;
  }
  return false;
}

// Whether faces f and g, which share only vertex v, meet elsewhere at positions x (exact).
bool star_faces_cross(const std::vector<glm::vec4>& x, std::uint32_t v, const glm::uvec4& f, const glm::uvec4& g) {
  if (clearly_apart(x, v, f, g)) return false;
  std::vector<glm::dvec3> p;
  TriangleIds ids[2];
  std::uint32_t seen[6] = {};
  auto local = [&](std::uint32_t v) {
    for (std::uint32_t k = 0; k < p.size(); ++k)
      if (seen[k] == v) return k;
    seen[p.size()] = v;
    p.push_back(at(x, v));
    return std::uint32_t(p.size() - 1);
  };
  for (int c = 0; c < 3; ++c) ids[0][c] = local(f[c]);
  for (int c = 0; c < 3; ++c) ids[1][c] = local(g[c]);
  return mesh_faces_intersect(p, ids[0], ids[1]);
}

std::size_t shared_corners(const glm::uvec4& f, const glm::uvec4& g) {
  std::size_t n = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) n += f[a] == g[b];
  return n;
}

// Whether two faces around vertex v that share only v cross at x1 but not at x0 (the collision
// search skips them, and neither face need fold for it: a flap of a fan can swing through
// another, on one sheet or across a junction). `moved` flags the faces with a corner that moves.
bool star_crosses(const FractureSurface& s, std::uint32_t v, const std::vector<glm::vec4>& x0,
                  const std::vector<glm::vec4>& x1, const std::vector<char>& moved) {
  const std::uint32_t b = s.vf_offsets[v], e = s.vf_offsets[v + 1];
  for (std::uint32_t i = b; i < e; ++i)
    for (std::uint32_t k = i + 1; k < e; ++k) {
      if (!moved[s.vf_faces[i]] && !moved[s.vf_faces[k]]) continue;
      const glm::uvec4 f = s.faces[s.vf_faces[i]], g = s.faces[s.vf_faces[k]];
      if (shared_corners(f, g) != 1) continue;
      if (star_faces_cross(x1, v, f, g) && !star_faces_cross(x0, v, f, g)) return true;
    }
  return false;
}

// The vertices whose stars star_crosses, ascending (judged side by side; the list does not
// depend on the thread count).
std::vector<std::uint32_t> crossing_stars(const FractureSurface& s, const std::vector<glm::vec4>& x0,
                                          const std::vector<glm::vec4>& x1, int threads) {
  std::vector<char> moved(s.faces.size());
  parallel_chunks(moved.size(), chunk_count(moved.size(), 4096), threads, [&](std::size_t, std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) moved[j] = moves(x0, x1, s.faces[j]);
  });
  const std::size_t n = s.vf_offsets.size() - 1;
  std::vector<char> crossed(n, 0);
  parallel_chunks(n, chunk_count(n, 1024), threads, [&](std::size_t, std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) crossed[v] = star_crosses(s, std::uint32_t(v), x0, x1, moved);
  });
  std::vector<std::uint32_t> out;
  for (std::size_t v = 0; v < n; ++v)
    if (crossed[v]) out.push_back(std::uint32_t(v));
  return out;
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

std::size_t hold_star_crossings(const FractureSurface& s, const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1,
                                int threads) {
  std::size_t held = 0;
  for (std::vector<std::uint32_t> stars = crossing_stars(s, x0, x1, threads); !stars.empty();
       stars = crossing_stars(s, x0, x1, threads))
    for (const std::uint32_t v : stars)
      for (std::uint32_t k = s.vf_offsets[v]; k < s.vf_offsets[v + 1]; ++k) held += hold(s.faces[s.vf_faces[k]], x0, x1);
  return held;
}

bool motion_crosses_stars(const FractureSurface& s, const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1,
                          int threads) {
  return !crossing_stars(s, x0, x1, threads).empty();
}

bool rises_at_first_order(double rise_double, double rise) {
  return rise_double > 0.0 && rise > 0.0 && 4.0 * rise >= rise_double;
}

// Each round holds at least one more vertex at x0 or is the last.
std::size_t hold_coincident_rim(const FractureSurface& s, const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1) {
  std::size_t held = 0;
  for (bool changed = true; changed;) {
    changed = false;
    std::map<std::array<float, 3>, std::uint32_t> at;
    for (std::uint32_t v = 0; v < x1.size(); ++v) {
      if (!(s.vertex_flags[v] & kVertexBoundary)) continue;
      const auto [it, fresh] = at.emplace(std::array<float, 3>{x1[v].x, x1[v].y, x1[v].z}, v);
      if (fresh) continue;
      for (const std::uint32_t w : {it->second, v})
        if (x1[w] != x0[w]) {
          x1[w] = x0[w];
          ++held;
          changed = true;
        }
    }
  }
  return held;
}

}  // namespace fracref
