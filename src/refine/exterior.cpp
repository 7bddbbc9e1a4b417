#include "refine/exterior.hpp"

#include "io/mesh_stats.hpp"
#include "util/error.hpp"

namespace fracref {

ExteriorSurface make_exterior(const MeshSoup& mesh, const std::string& what) {
  MeshStats st = mesh_stats(mesh);
  if (!st.closed)
    throw InputError(what + ": the exterior surface is not closed (" + std::to_string(st.boundary_edges) +
                     " boundary edges, " + std::to_string(st.non_manifold_edges) + " non-manifold edges)");
  ExteriorSurface b;
  b.bvh = build_bvh(mesh.positions, mesh.triangles);
  b.ccd = prepare_static_ccd_mesh(mesh.positions, mesh.triangles);
  b.bbox_min = st.bbox_min;
  b.bbox_max = st.bbox_max;
  return b;
}

}  // namespace fracref
