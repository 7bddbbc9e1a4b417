#pragma once
// Exact intersection guard for local edits of a triangle soup (the fracture surface S): before an
// edit replaces some faces by others, test that the new faces meet no other face.
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "geom/bvh.hpp"
#include "geom/intersect.hpp"
#include "geom/quad_prism.hpp"
#include "util/parallel.hpp"

namespace fracref {

/// A snapshot of a mesh (positions, faces, a box tree over the faces) plus the edits accepted
/// since: replaced faces are dropped from the tests, new faces and new vertices are added.
/// \pre the mesh's positions do not change while the guard is in use (only faces are replaced).
class FaceGuard {
 public:
  /// `threads` build the box tree (the result never depends on it).
  /// \pre every face index is below positions.size().
  FaceGuard(std::vector<glm::dvec3> positions, std::vector<TriangleIds> faces, int threads = default_threads());

  /// A guard for edits inside known regions: only the faces whose box overlaps one of `regions`
  /// are indexed (a face outside every region cannot meet a new face inside one), which on a
  /// large surface costs a scan instead of a tree over all of its faces.
  /// \pre every face index is below positions.size().
  /// \throw RunError from clear() when the new faces' box is not inside one of the regions (a
  /// caller's error: faces outside them were not indexed).
  FaceGuard(std::vector<glm::dvec3> positions, std::vector<TriangleIds> faces, const std::vector<Aabb>& regions,
            int threads = default_threads());

  /// Adds a vertex that the new faces may use; returns its id (after the mesh's vertices).
  std::uint32_t add_vertex(const glm::dvec3& p);

  /// Whether `faces` (vertex ids of the mesh or added vertices) meet no face of S other than the
  /// `replaced` ones and those replaced before, nor any face accepted before (exact; faces that
  /// share vertices are judged as mesh_faces_intersect does).
  bool clear(std::initializer_list<TriangleIds> faces, std::initializer_list<std::uint32_t> replaced) const {
    return clear(std::vector<TriangleIds>(faces), std::vector<std::uint32_t>(replaced));
  }
  /// `reach` >= 0 promises that every point of `faces` lies within `reach` of one of the
  /// `replaced` faces (a split whose new vertex is at most `reach` off a replaced face): faces
  /// farther than that from all of them are passed over without the exact test (same answer).
  bool clear(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced,
             double reach = -1.0) const;

  /// The first face of the snapshot, other than `replaced` and gone or not, that `faces` meet
  /// (in a fixed order), or kNoHit. Reads only what the constructor set up, so edits can be
  /// tested side by side (on several threads) before clear_given() decides each in turn.
  /// \throw RunError as clear().
  static constexpr std::uint32_t kNoHit = 0xffffffffu;
  std::uint32_t first_snapshot_hit(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced,
                                   double reach = -1.0) const;

  /// clear(faces, replaced) for `hit` = first_snapshot_hit(faces, replaced): no hit, or one
  /// that is not gone, decide the snapshot's part at once; a hit gone since is tested again.
  bool clear_given(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced,
                   std::uint32_t hit, double reach = -1.0) const;

  /// Records an accepted edit: `replaced` faces of the mesh are gone, `faces` exist.
  void accept(std::initializer_list<TriangleIds> faces, std::initializer_list<std::uint32_t> replaced) {
    accept(std::vector<TriangleIds>(faces), std::vector<std::uint32_t>(replaced));
  }
  void accept(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced);

 private:
  Aabb box_of(const TriangleIds& t) const;
  // The new faces' boxes, and each one's own flat prism: a face of S that the prism separates
  // from its new face meets it nowhere but at shared corners, and needs no exact test (most of
  // the faces near a long rim chord: coplanar neighbours beyond its edges, or off its plane).
  struct NewShapes {
    std::vector<Aabb> boxes;
    std::vector<std::optional<QuadPrism>> prisms;
  };
  NewShapes shapes_of(const std::vector<TriangleIds>& faces) const;
  // Per replaced face, the prism (grown by clear's `reach`) its new faces lie in; none: every
  // face is tested.
  using Slabs = std::vector<QuadPrism>;
  Slabs slabs(const std::vector<std::uint32_t>& replaced, double reach) const;
  bool beyond(const Slabs& slabs, const TriangleIds& g) const;
  // Whether one of `faces` (with their `boxes`) meets face g (exact).
  bool meets(const std::vector<TriangleIds>& faces, const NewShapes& shapes, std::uint32_t g, const Slabs& near) const;
  // The snapshot faces other than `replaced` whose boxes overlap the box of `faces`, less those
  // in a subtree whose box every prism of `near` separates (beyond() would hold for them).
  std::vector<std::uint32_t> snapshot_near(const std::vector<TriangleIds>& faces,
                                           const std::vector<std::uint32_t>& replaced, const Slabs& near) const;
  // Whether `faces` meet a face of the snapshot that is neither gone nor in `replaced`.
  bool meets_snapshot(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced,
                      const Slabs& near) const;
  // Whether `faces` meet no face accepted so far.
  bool clear_of_accepted(const std::vector<TriangleIds>& faces, const Slabs& near) const;
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
  Bvh bvh_;                          // item k: mesh face k, or indexed_[k] when restricted_
  bool restricted_ = false;          // built with regions: only faces near them are indexed
  std::vector<std::uint32_t> indexed_;
  std::vector<Aabb> regions_;
  Bvh region_tree_;
  std::vector<Aabb> new_boxes_;      // per accepted new face
  std::vector<Run> runs_;
};

}  // namespace fracref
