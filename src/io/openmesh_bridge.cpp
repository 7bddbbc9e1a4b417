#include "io/openmesh_bridge.hpp"

#include <OpenMesh/Core/System/omstream.hh>

#include <array>
#include <vector>

#include "util/error.hpp"

namespace fracref {
namespace {

std::string face_text(std::size_t t, const std::array<std::uint32_t, 3>& v) {
  return "face " + std::to_string(t) + " (" + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
         std::to_string(v[2]) + ")";
}

// Why OpenMesh would refuse triangle `v`, or "" when it is expected to accept it. The checks
// mirror PolyConnectivity::add_face: an edge whose halfedge in the face's direction already has
// a face, then a vertex that is already surrounded by faces.
std::string rejection(const TriMesh& mesh, const std::array<std::uint32_t, 3>& v) {
  for (int i = 0; i < 3; ++i) {
    auto a = mesh.vertex_handle(v[i]), b = mesh.vertex_handle(v[(i + 1) % 3]);
    auto he = mesh.find_halfedge(a, b);
    if (!he.is_valid() || mesh.is_boundary(he)) continue;
    std::string edge = std::to_string(v[i]) + "-" + std::to_string(v[(i + 1) % 3]);
    if (!mesh.is_boundary(mesh.opposite_halfedge_handle(he))) return "would make edge " + edge + " non-manifold";
    return "uses edge " + edge + " in the same direction as face " + std::to_string(mesh.face_handle(he).idx()) +
           " (inconsistent winding)";
  }
  for (std::uint32_t w : v)
    if (!mesh.is_boundary(mesh.vertex_handle(w))) return "would make vertex " + std::to_string(w) + " non-manifold";
  return "";
}

// OpenMesh reports its refusals on omerr; ours are the InputError, so its line is muted.
class MutedOmerr {
 public:
  MutedOmerr() : was_enabled_(omerr().is_enabled()) { omerr().disable(); }
  ~MutedOmerr() { if (was_enabled_) omerr().enable(); }

 private:
  bool was_enabled_;
};

}  // namespace

TriMesh to_trimesh(const MeshSoup& soup, const std::string& what) {
  TriMesh mesh;
  mesh.reserve(soup.positions.size(), soup.triangles.size() * 3 / 2 + 3, soup.triangles.size());
  for (const glm::dvec3& p : soup.positions) mesh.add_vertex(TriMesh::Point(p.x, p.y, p.z));
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    const auto& v = soup.triangles[t];
    for (std::uint32_t w : v)
      if (w >= soup.positions.size())
        throw InputError(what + ": " + face_text(t, v) + " references vertex " + std::to_string(w) + " of " +
                         std::to_string(soup.positions.size()));
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
      throw InputError(what + ": " + face_text(t, v) + " repeats a vertex");
    std::string why = rejection(mesh, v);
    if (!why.empty()) throw InputError(what + ": " + face_text(t, v) + " " + why);
    TriMesh::FaceHandle f;
    {
      MutedOmerr muted;
      f = mesh.add_face(mesh.vertex_handle(v[0]), mesh.vertex_handle(v[1]), mesh.vertex_handle(v[2]));
    }
    if (!f.is_valid())
      throw InputError(what + ": " + face_text(t, v) +
                       " cannot be linked into the mesh (a vertex of it would get a non-manifold fan)");
  }
  return mesh;
}

MeshSoup from_trimesh(const TriMesh& mesh) {
  MeshSoup soup;
  std::vector<std::uint32_t> index(mesh.n_vertices(), 0);
  soup.positions.reserve(mesh.n_vertices());
  for (auto vh : mesh.vertices()) {
    index[vh.idx()] = static_cast<std::uint32_t>(soup.positions.size());
    const auto& p = mesh.point(vh);
    soup.positions.emplace_back(p[0], p[1], p[2]);
  }
  for (auto fh : mesh.faces()) {
    std::array<std::uint32_t, 3> tri{};
    int corner = 0;
    for (auto vh : fh.vertices()) {
      if (corner == 3) break;
      tri[corner++] = index[vh.idx()];
    }
    soup.triangle_polygon.push_back(static_cast<std::uint32_t>(soup.triangles.size()));
    soup.triangles.push_back(tri);
  }
  soup.polygons = soup.triangles.size();
  return soup;
}

}  // namespace fracref
