// The demo scenes' tet meshes of curved exteriors: coarse/tet_lattice.hpp's isosurface stuffing,
// with the extra requirement that the hull be a 2-manifold (the generated pieces rely on it).
#include "scenegen/scenegen_internal.hpp"
#include "util/error.hpp"

namespace fracref::scenegen_detail {

TetSet stuffed_tets(const TriMesh& exterior, const LatticeSpec& spec, double warp) {
  TetSet set = fracref::stuffed_tets(exterior.positions, exterior.triangles, spec, warp);
  if (!surface_defects(tet_faces(set).hull).empty())
    throw RunError("scenegen: the stuffed tets' hull is not a 2-manifold (the lattice is too coarse for the exterior)");
  return set;
}

}  // namespace fracref::scenegen_detail
