#pragma once
// The exterior surface B for the refiner: closest-point projection (the boundary constraint) and
// inside tests (interior vertices must stay inside the object).
#include <vector>

#include <glm/glm.hpp>

#include "geom/bvh.hpp"
#include "geom/ccd.hpp"
#include "io/mesh_soup.hpp"
#include "rim/exterior_mesh.hpp"

namespace fracref {

struct ExteriorSurface {
  Bvh bvh;                         ///< keeps B's positions and triangles
  StaticCcdMesh ccd;               ///< B prepared once for continuous collision detection
  glm::dvec3 bbox_min{0.0}, bbox_max{0.0};
  rim::ExteriorMesh mesh;          ///< B's adjacency, for S's rim embedded in B (empty: built on use)

  double diagonal() const { return glm::length(bbox_max - bbox_min); }
  glm::dvec3 closest_point(const glm::dvec3& p) const { return fracref::closest_point(bvh, p).point; }
  double squared_distance(const glm::dvec3& p) const { return fracref::closest_point(bvh, p).squared_distance; }
  bool contains(const glm::dvec3& p) const { return point_in_mesh(bvh, p); }
  /// Whether the closed triangle (a, b, c) shares a point with B (exact).
  bool meets(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) const;
  /// B's outward unit normal at its triangle `t`.
  glm::dvec3 normal(std::uint32_t t) const;
};

/// Builds the exterior from a mesh. \throw InputError naming `what` when the mesh is not one
/// closed, edge- and vertex-manifold, consistently and outward wound surface (checked through
/// the OpenMesh halfedge structure), has no triangles, or intersects itself (names two faces).
ExteriorSurface make_exterior(const MeshSoup& mesh, const std::string& what);

}  // namespace fracref
