#pragma once
// Exact intersection guard for local edits of a triangle soup (the fracture surface S): before an
// edit replaces some faces by others, test that the new faces meet no other face.
#include <cstdint>
#include <initializer_list>
#include <vector>

#include <glm/glm.hpp>

#include "geom/bvh.hpp"
#include "geom/intersect.hpp"

namespace fracref {

/// A snapshot of a mesh (positions, faces, a box tree over the faces) plus the edits accepted
/// since: replaced faces are dropped from the tests, new faces and new vertices are added.
/// \pre the mesh's positions do not change while the guard is in use (only faces are replaced).
class FaceGuard {
 public:
  /// \pre every face index is below positions.size().
  FaceGuard(std::vector<glm::dvec3> positions, std::vector<TriangleIds> faces);

  /// Adds a vertex that the new faces may use; returns its id (after the mesh's vertices).
  std::uint32_t add_vertex(const glm::dvec3& p);

  /// Whether `faces` (vertex ids of the mesh or added vertices) meet no face of S other than the
  /// `replaced` ones and those replaced before, nor any face accepted before (exact; faces that
  /// share vertices are judged as mesh_faces_intersect does).
  bool clear(std::initializer_list<TriangleIds> faces, std::initializer_list<std::uint32_t> replaced) const {
    return clear(std::vector<TriangleIds>(faces), std::vector<std::uint32_t>(replaced));
  }
  bool clear(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced) const;

  /// clear() in two parts, for many candidate edits judged at once. First, for every edit k, the
  /// faces of the snapshot other than replaced[k] that faces[k] meet, ignoring every edit
  /// accepted so far (independent per edit: run on `threads` threads, the answer does not depend
  /// on their number). Then clear(faces, replaced) is exactly: every one of those blockers is
  /// gone() and clear_of_accepted(faces).
  std::vector<std::vector<std::uint32_t>> snapshot_blockers(const std::vector<std::vector<TriangleIds>>& faces,
                                                            const std::vector<std::vector<std::uint32_t>>& replaced,
                                                            int threads) const;
  bool gone(std::uint32_t snapshot_face) const { return gone_[snapshot_face] != 0; }
  /// Whether `faces` meet no face accepted so far.
  bool clear_of_accepted(const std::vector<TriangleIds>& faces) const;

  /// For a batch of candidate edits judged in order, for every edit k the earlier edits j < k
  /// whose faces meet faces[k] (exact, as mesh_faces_intersect), ascending. With it the batch needs
  /// no accept(): edit k is clear of the accepted ones exactly when none of them is in its list.
  /// Runs on `threads` threads; the answer does not depend on their number.
  std::vector<std::vector<std::uint32_t>> batch_conflicts(const std::vector<std::vector<TriangleIds>>& faces,
                                                          int threads) const;

  /// Records an accepted edit: `replaced` faces of the mesh are gone, `faces` exist.
  void accept(std::initializer_list<TriangleIds> faces, std::initializer_list<std::uint32_t> replaced) {
    accept(std::vector<TriangleIds>(faces), std::vector<std::uint32_t>(replaced));
  }
  void accept(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced);

 private:
  Aabb box_of(const TriangleIds& t) const;
  // Appends the snapshot faces other than `replaced` that `faces` meet (gone ones left out when
  // skip_gone; only the first when first_only).
  void snapshot_hits(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced, bool skip_gone,
                     bool first_only, std::vector<std::uint32_t>& out) const;
  void index_new_boxes();

  // Accepted faces' boxes are indexed by trees over contiguous runs of new_boxes_ whose sizes
  // shrink along the list (merged like binary counters), plus a short unindexed tail: a clear()
  // after n acceptances costs O(log² n) rather than O(n) (flips accept tens of thousands).
  struct Run {
    std::size_t begin = 0, end = 0;
    Bvh tree;
  };

  std::vector<glm::dvec3> x_;
  std::vector<TriangleIds> faces_;   // the mesh's faces, then the accepted new ones
  std::size_t s_faces_ = 0;
  std::vector<char> gone_;           // per mesh face
  Bvh bvh_;
  std::vector<Aabb> new_boxes_;      // per accepted new face
  std::vector<Run> runs_;
};

}  // namespace fracref
