#include "refine/exterior.hpp"

#include <future>

#include "geom/intersect.hpp"
#include "io/mesh_stats.hpp"
#include "io/openmesh_bridge.hpp"
#include "util/error.hpp"

namespace fracref {

bool ExteriorSurface::meets(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) const {
  Aabb box;
  for (const glm::dvec3& p : {a, b, c}) box.expand(p);
  thread_local std::vector<std::uint32_t> hits;  // called per rim face on every step: no allocation each
  hits.clear();
  query_box(bvh, box, hits);
  for (std::uint32_t h : hits) {
    const auto& q = bvh.triangles[h];
    if (triangles_intersect({a, b, c}, {bvh.positions[q[0]], bvh.positions[q[1]], bvh.positions[q[2]]})) return true;
  }
  return false;
}

glm::dvec3 ExteriorSurface::normal(std::uint32_t t) const {
  const auto& q = bvh.triangles[t];
  const glm::dvec3 n = glm::cross(bvh.positions[q[1]] - bvh.positions[q[0]], bvh.positions[q[2]] - bvh.positions[q[0]]);
  const double len = glm::length(n);
  return len > 0.0 ? n / len : glm::dvec3(0.0);
}

namespace {

std::string face_text(const MeshSoup& mesh, std::uint32_t f) {
  const auto& t = mesh.triangles[f];
  return std::to_string(f) + " (" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")";
}

// A self-intersecting exterior has no inside to partition: refused here rather than after the
// refinement, when its pieces cannot be closed.
void check_not_self_intersecting(const MeshSoup& mesh, const std::string& what) {
  const std::vector<TriangleIds> faces(mesh.triangles.begin(), mesh.triangles.end());
  const auto pairs = find_self_intersections(mesh.positions, faces, 1);
  if (!pairs.empty())
    throw InputError(what + ": the exterior surface intersects itself: faces " + face_text(mesh, pairs[0].first) +
                     " and " + face_text(mesh, pairs[0].second) + " cross (faces and vertices counted from 0)");
}

}  // namespace

ExteriorSurface make_exterior(const MeshSoup& mesh, const std::string& what) {
  // The collision trees are built beside the checks below (an error of the checks still comes
  // first: the trees' own errors are raised only once the checks have passed).
  auto ccd = std::async(std::launch::async, [&mesh] { return prepare_static_ccd_mesh(mesh.positions, mesh.triangles, 0.0, 1); });
  MeshStats st = mesh_stats(mesh);
  if (!st.closed)
    throw InputError(what + ": the exterior surface is not closed (" + std::to_string(st.boundary_edges) +
                     " boundary edges, " + std::to_string(st.non_manifold_edges) + " non-manifold edges)");
  // Built through OpenMesh deliberately: a face that would make a complex edge or vertex, or
  // that is wound against its neighbours, is an error naming it (never OpenMesh's silent fix).
  TriMesh halfedges = to_trimesh(mesh, what);
  if (st.components != 1)
    throw InputError(what + ": the exterior surface has " + std::to_string(st.components) +
                     " separate components; fracref needs one closed surface");
  double volume = 0.0;
  for (const auto& t : mesh.triangles)
    volume += glm::dot(mesh.positions[t[0]], glm::cross(mesh.positions[t[1]], mesh.positions[t[2]])) / 6.0;
  if (!(volume > 0.0))
    throw InputError(what + ": the exterior surface is wound inward (its signed volume is " + std::to_string(volume) +
                     "); reverse its faces");
  check_not_self_intersecting(mesh, what);
  ExteriorSurface b;
  b.bvh = build_bvh(mesh.positions, mesh.triangles);
  b.ccd = ccd.get();
  b.bbox_min = st.bbox_min;
  b.bbox_max = st.bbox_max;
  b.mesh = rim::make_exterior_mesh(mesh);
  return b;
}

}  // namespace fracref
