#pragma once
// The bridge between triangle soups and OpenMesh halfedge meshes in double precision.
#include <string>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "io/mesh_soup.hpp"

namespace fracref {

/// OpenMesh traits with double-precision points and normals.
struct DoubleTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};

/// The halfedge triangle mesh used for the exterior surface and the output pieces.
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

/// Builds a TriMesh with one vertex per position (unused ones included, same order) and one
/// face per triangle (same order, same winding), so vertex i and face t keep their indices.
/// A halfedge mesh cannot hold what OpenMesh would otherwise patch by duplicating vertices, so
/// every such triangle is an error instead:
///   "<what>: face 12 (3 7 9) would make edge 3-7 non-manifold"          (third face on an edge)
///   "<what>: face 12 (3 7 9) uses edge 3-7 in the same direction as face 4 (inconsistent winding)"
///   "<what>: face 12 (3 7 9) would make vertex 3 non-manifold"          (a second fan at a vertex)
/// Vertex and face indices in messages are 0-based.
/// \throw InputError naming `what` for such faces, for a repeated vertex in a triangle and for
///        an index out of range.
TriMesh to_trimesh(const MeshSoup& soup, const std::string& what);

/// The soup of `mesh`: positions of its non-deleted vertices (in order), its non-deleted faces as
/// triangles (in order, renumbered); triangle_polygon is the identity and polygons the face count.
/// \pre every face of `mesh` is a triangle (always true for a TriMesh).
MeshSoup from_trimesh(const TriMesh& mesh);

}  // namespace fracref
