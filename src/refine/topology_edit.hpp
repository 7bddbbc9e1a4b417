#pragma once
// Topology edits of the fracture surface S during adaptive refinement (paper 4.4): 1-to-3 face
// splits, edge splits across any number of faces, edge flips; and the refinement tree that
// records where every new vertex came from.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "surface/fracture_surface.hpp"

namespace fracref {

/// Per vertex of S, up to three (parent, weight) pairs: the vertex was created at
/// Σ_k weights[k] · x(parents[k]) as it was at that moment. An original (coarse) vertex is its
/// own parent with weight 1. Parents are older vertices, so the pairs form a tree whose leaves
/// are the coarse vertices (paper 4.4, Figure 6).
struct RefinementTree {
  std::vector<glm::uvec3> parents;
  std::vector<glm::vec3> weights;

  /// A tree for `n` original vertices.
  static RefinementTree identity(std::size_t n);
  /// The leaves (coarse vertices) and their weights reached from vertex v, weights multiplied
  /// along the path and merged per leaf, ascending by leaf id.
  std::vector<std::pair<std::uint32_t, double>> leaf_weights(std::uint32_t v) const;
};

/// One split chosen by the refiner, at a point given by weights on the element's vertices.
struct SplitRequest {
  enum Kind : std::uint8_t { kFace, kEdge } kind;
  std::uint32_t element;  ///< face id (kFace) or edge id (kEdge) of S's current adjacency
  glm::vec3 weights;      ///< kFace: barycentric on the face's (x, y, z); kEdge: (1−t, t, 0) on (edges[e].x, .y)
};

/// Applies the splits (each element at most once; no face may be touched by two requests),
/// appending new vertices (positions from the weights) and faces that keep their parent face's
/// pieces, records the new vertices in `tree`, then rebuilds the adjacency.
/// A face split turns (a, b, c) into (a, b, s), (b, c, s), (c, a, s); an edge split turns every
/// face (x, y, z) traversing the edge as x→y into (x, s, z), (s, y, z).
/// When `positions` is given (one per request) the new vertex is placed there instead of at the
/// weighted point (a boundary sample projected onto the exterior); the tree keeps the weights.
/// \pre adjacency current; requests reference valid elements; tree covers every vertex.
/// \return the number of vertices added.
/// The adjacency is rebuilt by rebuild_after_splits. With `deferred_origin` only the edge table
/// is (rebuild_edge_table), and the new faces' origins are appended to it: for a caller that
/// splits again right away and calls rebuild_after_splits once at the end; the new vertices'
/// flags are 0 until then (right for a vertex inside an interior regular edge or a face).
std::size_t apply_splits(FractureSurface& s, RefinementTree& tree, const std::vector<SplitRequest>& requests,
                         const std::vector<glm::vec3>* positions = nullptr,
                         std::vector<std::uint32_t>* deferred_origin = nullptr);

/// S after apply_splits(s, tree, requests, &positions) as far as collision tests read it:
/// positions, faces, face_pieces, vertex_flags (a new vertex on a split boundary edge flagged
/// boundary) and the edge table; the rest of the adjacency is not built. Much cheaper than a
/// copy and apply_splits. `parents`, when given, receives the new vertices' entries of the tree
/// (sized to the preview's vertices; entries of the old vertices left default).
/// \pre as apply_splits; one position per request.
FractureSurface split_preview(const FractureSurface& s, const std::vector<SplitRequest>& requests,
                              const std::vector<glm::vec3>& positions, RefinementTree* parents = nullptr);

/// Which of `requests` would make S cross itself, one flag per request (1: one of the faces it
/// makes meets a face of S, or one another request makes, other than where the mesh connects
/// them). A split keeps S's shape up to the rounding of its new vertex to float, which matters
/// only where two sheets of S touch; and a position off the element (a boundary sample put onto
/// the exterior) moves the faces around it. Exact (mesh_faces_intersect).
/// \pre as split_preview.
std::vector<char> splits_that_cross(const FractureSurface& s, const std::vector<SplitRequest>& requests,
                                    const std::vector<glm::vec3>& positions);

/// Flips the regular edge `edge` shared by faces (a, b, c) and (b, a, d) into (c, a, d), (d, b, c).
/// Returns false, changing nothing, when the edge is special, its faces are wound inconsistently
/// or separate different pieces, or the edge c–d already exists. Does NOT rebuild the adjacency:
/// the caller flips a set of edges with disjoint faces, then calls rebuild_adjacency().
/// \pre adjacency current.
bool flip_edge(FractureSurface& s, std::uint32_t edge);

/// The two opposite vertices (c, d) of a regular edge, as flip_edge would use them, and the two
/// faces; false when the edge cannot be flipped (see flip_edge).
bool flip_candidates(const FractureSurface& s, std::uint32_t edge, glm::uvec2& opposite, glm::uvec2& faces);

/// flip_candidates without its last test, that the edge c–d does not exist yet (an edge-table
/// search, the costliest part: callers with tests of their own run it last).
bool flip_quad(const FractureSurface& s, std::uint32_t edge, glm::uvec2& opposite, glm::uvec2& faces);

}  // namespace fracref
