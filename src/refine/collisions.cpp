#include "refine/collisions.hpp"

#include "geom/parallel.hpp"

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
// need the (costlier) inside test.
std::size_t keep_inside(const FractureSurface& s, const ExteriorSurface& b, const std::vector<glm::vec4>& x0,
                        std::vector<glm::vec4>& x1) {
  std::size_t reset = 0;
  for (std::size_t i = 0; i < x1.size(); ++i) {
    if (s.vertex_flags[i] & kVertexBoundary) continue;
    glm::dvec3 p0(glm::vec3(x0[i])), p1(glm::vec3(x1[i]));
    double travel = glm::distance(p0, p1);
    if (travel == 0.0) continue;
    if (b.squared_distance(p1) > travel * travel) continue;
    if (!b.contains(p1)) x1[i] = x0[i], ++reset;
  }
  return reset;
}

}  // namespace

std::size_t apply_collision_constraints(const FractureSurface& s, const ExteriorSurface& b,
                                        const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1) {
  return keep_inside(s, b, x0, x1);
}

}  // namespace fracref
