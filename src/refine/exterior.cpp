#include "refine/exterior.hpp"

#include "io/mesh_stats.hpp"
#include "io/openmesh_bridge.hpp"
#include "util/error.hpp"

namespace fracref {

ExteriorSurface make_exterior(const MeshSoup& mesh, const std::string& what) {
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
  ExteriorSurface b;
  b.bvh = build_bvh(mesh.positions, mesh.triangles);
  b.ccd = prepare_static_ccd_mesh(mesh.positions, mesh.triangles);
  b.bbox_min = st.bbox_min;
  b.bbox_max = st.bbox_max;
  return b;
}

}  // namespace fracref
