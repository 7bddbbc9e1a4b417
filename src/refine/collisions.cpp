#include "refine/collisions.hpp"

#include <algorithm>

#include "geom/ccd.hpp"

namespace fracref {

void project_boundary_vertices(FractureSurface& s, const ExteriorSurface& b) {
  for (std::size_t i = 0; i < s.positions.size(); ++i)
    if (s.vertex_flags[i] & kVertexBoundary)
      s.positions[i] = glm::vec4(glm::vec3(b.closest_point(glm::dvec3(glm::vec3(s.positions[i])))), 1.0f);
}

void apply_boundary_constraint(const FractureSurface& s, const ExteriorSurface& b, const std::vector<glm::vec4>&,
                               std::vector<glm::vec4>& x1) {
  for (std::size_t i = 0; i < x1.size(); ++i)
    if (s.vertex_flags[i] & kVertexBoundary)
      x1[i] = glm::vec4(glm::vec3(b.closest_point(glm::dvec3(glm::vec3(x1[i])))), 1.0f);
}

namespace {

// An interior vertex that ends closer to B than it travelled may have crossed it: only those
// need the (costlier) inside test. A cached lower bound of the distance to B, lowered by the
// travel of every step, spares most of the closest-point queries too.
std::size_t keep_inside(const FractureSurface& s, const ExteriorSurface& b, const std::vector<glm::vec4>& x0,
                        std::vector<glm::vec4>& x1, std::vector<float>* clearance) {
  std::vector<float> scratch;
  std::vector<float>& c = clearance ? *clearance : scratch;
  c.resize(x1.size(), -1.0f);
  std::size_t reset = 0;
  for (std::size_t i = 0; i < x1.size(); ++i) {
    if (s.vertex_flags[i] & kVertexBoundary) continue;
    glm::dvec3 p0(glm::vec3(x0[i])), p1(glm::vec3(x1[i]));
    double travel = glm::distance(p0, p1);
    if (c[i] >= 0.0f && double(c[i]) > 2.0 * travel) {
      c[i] = float(c[i] - travel);
      continue;
    }
    double d1 = std::sqrt(b.squared_distance(p1));
    if (d1 > travel) {
      c[i] = float(d1 * (1.0 - 1e-6));
      continue;
    }
    if (!b.contains(p1)) x1[i] = x0[i], ++reset, c[i] = -1.0f;
    else c[i] = float(d1 * (1.0 - 1e-6));
  }
  return reset;
}

std::vector<glm::dvec3> to_double(const std::vector<glm::vec4>& x) {
  std::vector<glm::dvec3> out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = glm::dvec3(glm::vec3(x[i]));
  return out;
}

// The faces that may touch B during the step. Distance to B is 1-Lipschitz, so every point of a
// face stays at least (smallest corner clearance − longest edge − largest corner travel) away
// from B; faces with a positive bound cannot meet it and are left out of the (costly) test.
std::vector<std::array<std::uint32_t, 3>> faces_near_exterior(const std::vector<std::array<std::uint32_t, 3>>& tris,
                                                              const std::vector<glm::vec4>& x0,
                                                              const std::vector<glm::vec4>& x1,
                                                              const std::vector<float>& clearance) {
  if (clearance.size() != x0.size()) return tris;
  std::vector<std::array<std::uint32_t, 3>> near;
  for (const auto& t : tris) {
    double lowest = 1e300, longest = 0.0, travel = 0.0;
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 a(glm::vec3(x0[t[k]])), c(glm::vec3(x0[t[(k + 1) % 3]]));
      lowest = std::min(lowest, double(clearance[t[k]]) < 0.0 ? -1.0 : double(clearance[t[k]]));
      longest = std::max(longest, glm::distance(a, c));
      travel = std::max(travel, double(glm::distance(glm::vec3(x0[t[k]]), glm::vec3(x1[t[k]]))));
    }
    if (lowest - longest - travel <= 1e-6 * (longest + 1e-30) + 1e-12) near.push_back(t);
  }
  return near;
}

}  // namespace

std::size_t apply_collision_constraints(const FractureSurface& s, const ExteriorSurface& b,
                                        const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1,
                                        std::vector<float>* clearance) {
  const std::vector<float> clearance_at_x0 = clearance ? *clearance : std::vector<float>();
  std::size_t stopped = keep_inside(s, b, x0, x1, clearance);
  std::vector<std::array<std::uint32_t, 3>> tris(s.faces.size());
  for (std::size_t f = 0; f < s.faces.size(); ++f) tris[f] = {s.faces[f].x, s.faces[f].y, s.faces[f].z};
  const std::vector<std::array<std::uint32_t, 3>> near_b = faces_near_exterior(tris, x0, x1, clearance_at_x0);
  std::vector<std::uint8_t> on_b(x1.size(), 0);
  for (std::size_t i = 0; i < x1.size(); ++i) on_b[i] = (s.vertex_flags[i] & kVertexBoundary) ? 1 : 0;
  std::vector<std::array<std::uint32_t, 2>> edges(s.edges.size());
  for (std::size_t e = 0; e < s.edges.size(); ++e)
    edges[e] = {std::min(s.edges[e].x, s.edges[e].y), std::max(s.edges[e].x, s.edges[e].y)};
  StepCcdOptions opts;
  opts.ccd.tolerance = 1e-7 * b.diagonal();
  opts.skip_resting_pairs = true;  // resting pairs cannot change by freezing (see the loop's end)
  const std::vector<glm::dvec3> p0 = to_double(x0);
  // Each round resets every vertex of every colliding pair; the moving set shrinks strictly, so
  // the loop ends. After the first round only pairs with a vertex reset in the round before
  // can have changed, so only those are tested again.
  std::vector<std::uint8_t> reset_now(x1.size(), 0);
  for (int round = 0;; ++round) {
    opts.active_vertices = round > 0 ? &reset_now : nullptr;
    std::vector<glm::dvec3> p1 = to_double(x1);
    opts.edges = &edges;
    std::vector<CcdPair> pairs = find_step_collisions(p0, p1, tris, opts);
    opts.edges = nullptr;
    opts.ignored_vertices = &on_b;
    std::vector<CcdPair> with_b = find_step_collisions_with_static(p0, p1, near_b, b.ccd, opts);
    opts.ignored_vertices = nullptr;
    if (pairs.empty() && with_b.empty()) break;
    const std::size_t before = stopped;
    std::fill(reset_now.begin(), reset_now.end(), 0);
    auto freeze = [&](std::uint32_t v) {
      if (x1[v] != x0[v]) x1[v] = x0[v], reset_now[v] = 1, ++stopped;
    };
    for (const CcdPair& p : pairs)
      for (std::uint32_t v : p.vertices) freeze(v);
    for (const CcdPair& p : with_b) {
      if (p.kind == CcdKind::vertex_triangle) freeze(p.vertices[0]);
      else if (p.kind == CcdKind::triangle_vertex) freeze(p.vertices[1]), freeze(p.vertices[2]), freeze(p.vertices[3]);
      else freeze(p.vertices[0]), freeze(p.vertices[1]);
    }
    // A pair whose vertices all stay put was within the CCD tolerance before the step already
    // (conservative CCD reports such contacts): holding vertices back cannot change it.
    if (stopped == before) break;
  }
  return stopped;
}

}  // namespace fracref
