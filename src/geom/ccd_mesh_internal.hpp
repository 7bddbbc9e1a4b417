#pragma once
// What the two mesh-level searches of ccd.hpp share (ccd_mesh.cpp: a mesh against itself;
// ccd_static.cpp: against a static mesh): input checks, edges, swept boxes, travels.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "geom/bvh.hpp"
#include "geom/ccd.hpp"

namespace fracref::ccd_detail {

using glm::dvec3;
using Tris = std::vector<std::array<std::uint32_t, 3>>;
using Edge = std::array<std::uint32_t, 2>;

/// \throw InputError naming the first vertex with a coordinate that is not finite.
void check_positions(const std::vector<dvec3>& x, const char* what);
/// \throw InputError naming the first triangle with an index of n or more.
void check_triangles(const Tris& tris, std::size_t n, const char* what);
/// \throw InputError when flags is set and not n long.
void check_flags(const std::vector<std::uint8_t>* flags, std::size_t n, const char* what);
/// The triangles' unique edges (a < b), sorted.
std::vector<Edge> unique_edges(const Tris& tris);
/// |x1 - x0| per vertex.
std::vector<double> travels(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1, int threads);
/// The vertices below n that some triangle uses, in order.
std::vector<std::array<std::uint32_t, 1>> used_vertices(const Tris& tris, std::size_t n);
CcdPair vertex_pair(CcdKind kind, std::uint32_t v, const std::array<std::uint32_t, 3>& tri, std::uint32_t t);
/// Whether vertex v takes part in the pairs to test (StepCcdOptions::active_vertices and
/// skip_resting_pairs).
bool is_active(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1, const StepCcdOptions& o, std::size_t v);

// Box of the given vertices over the step, grown by `grow` rounded outward.
template <std::size_t N>
Aabb swept_box(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1, const std::array<std::uint32_t, N>& ids,
               double grow) {
  Aabb box;
  for (std::uint32_t v : ids) {
    box.expand(x0[v]);
    box.expand(x1[v]);
  }
  if (grow > 0.0) {
    const double inf = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = std::nextafter(box.lo[a] - grow, -inf);
      box.hi[a] = std::nextafter(box.hi[a] + grow, inf);
    }
  }
  return box;
}

template <std::size_t N>
std::vector<Aabb> swept_boxes(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1,
                              const std::vector<std::array<std::uint32_t, N>>& elements, double grow) {
  std::vector<Aabb> boxes(elements.size());
  for (std::size_t k = 0; k < elements.size(); ++k) boxes[k] = swept_box(x0, x1, elements[k], grow);
  return boxes;
}

}  // namespace fracref::ccd_detail
