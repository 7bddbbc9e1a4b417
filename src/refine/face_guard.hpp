#pragma once
// Exact intersection guard for local edits of the fracture surface: before an edit replaces some
// faces by others, test that the new faces meet no other face of S.
#include <cstdint>
#include <initializer_list>
#include <vector>

#include <glm/glm.hpp>

#include "geom/bvh.hpp"
#include "geom/intersect.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

/// A snapshot of S (positions, faces, a box tree over the faces) plus the edits accepted since:
/// replaced faces are dropped from the tests, new faces and new vertices are added.
/// \pre S's positions do not change while the guard is in use (only faces are replaced).
class FaceGuard {
 public:
  explicit FaceGuard(const FractureSurface& s);

  /// Adds a vertex that the new faces may use; returns its id (after S's vertices).
  std::uint32_t add_vertex(const glm::dvec3& p);

  /// Whether `faces` (vertex ids of S or added vertices) meet no face of S other than the
  /// `replaced` ones and those replaced before, nor any face accepted before (exact; faces that
  /// share vertices are judged as mesh_faces_intersect does).
  bool clear(std::initializer_list<TriangleIds> faces, std::initializer_list<std::uint32_t> replaced) const;

  /// Records an accepted edit: `replaced` faces of S are gone, `faces` exist.
  void accept(std::initializer_list<TriangleIds> faces, std::initializer_list<std::uint32_t> replaced);

 private:
  Aabb box_of(const TriangleIds& t) const;

  std::vector<glm::dvec3> x_;
  std::vector<TriangleIds> faces_;   // S's faces, then the accepted new ones
  std::size_t s_faces_ = 0;
  std::vector<char> gone_;           // per S face
  Bvh bvh_;
  std::vector<Aabb> new_boxes_;      // per accepted new face
};

}  // namespace fracref
