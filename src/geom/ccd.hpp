#pragma once
// Conservative continuous collision detection over one linear step, t in [0, 1]: every vertex
// moves on the straight line from its position at t = 0 to its position at t = 1.
//
// Method (inclusion-based root finding, after Tight-Inclusion CCD, Wang et al. 2021): the
// difference function F(t, u, v) between the two primitives (point minus triangle point, or
// edge point minus edge point) is multilinear in (t, u, v), so over a parameter box its range
// is the convex hull of its 8 corner values, and so is the range of n.F for any direction n.
// Corner values are evaluated in floating point with an a-priori rounding-error bound
// (162 u M per coordinate, u = 2^-53, M = the largest |coordinate| of the 8 input points, from
// Higham's gamma_n analysis of the evaluation order used). A box is discarded only when some
// coordinate axis, or one of two fixed directions (the closest-point directions of the
// primitives at t = 0 and t = 1), proves |F| > min_distance on the whole box; the others are
// bisected. Boxes cover their parent whatever the rounding of the split point, so no root is
// ever discarded: a collision is never missed. The answer is "collision" when a box whose
// image is narrower than `tolerance` on every axis survives, when no box can be split further,
// or when `max_iterations` boxes have been examined.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "geom/bvh.hpp"
#include "util/parallel.hpp"

namespace fracref {

struct CcdOptions {
  /// Report a collision when the primitives come closer than this (Euclidean; >= 0).
  double min_distance = 0.0;
  /// A surviving box whose image under F is narrower than this on every axis counts as a
  /// collision. Hence a reported collision means the primitives came within about
  /// sqrt(3) * tolerance + min_distance of each other (or the iteration cap was hit).
  double tolerance = 1e-6;
  /// Boxes examined before giving up; giving up answers "collision".
  int max_iterations = 1000000;
};

/// What one query did (diagnostics).
struct CcdStats {
  int boxes = 0;             ///< parameter boxes examined
  bool hit_cap = false;      ///< stopped at max_iterations
  bool solved = false;       ///< the distance filters let the query through to the box search
  /// The distance filter with the corners' own travels let the query through: once some corners
  /// are sent back to x0 the pair may collide (the filter with the travels relative to the
  /// corners' mean motion, which may have settled it, no longer holds then).
  bool near = false;
};

/// Whether point p (p0 -> p1) and triangle (a, b, c) (a0 -> a1, ...) come within
/// options.min_distance at some t in [0, 1]. Conservative: never false for a real contact.
/// \pre finite inputs, |coordinates| < 1e300.
bool ccd_vertex_triangle(const glm::dvec3& p0, const glm::dvec3& a0, const glm::dvec3& b0, const glm::dvec3& c0,
                         const glm::dvec3& p1, const glm::dvec3& a1, const glm::dvec3& b1, const glm::dvec3& c1,
                         const CcdOptions& options = {}, CcdStats* stats = nullptr);

/// The distance between the closed segments [p, q] and [r, s] (their closest points; a segment
/// of length 0 is its point).
double segment_distance(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r, const glm::dvec3& s);

/// Whether segment (a, b) and segment (c, d) come within options.min_distance at some t in
/// [0, 1]. Conservative: never false for a real contact. \pre as ccd_vertex_triangle.
bool ccd_edge_edge(const glm::dvec3& a0, const glm::dvec3& b0, const glm::dvec3& c0, const glm::dvec3& d0,
                   const glm::dvec3& a1, const glm::dvec3& b1, const glm::dvec3& c1, const glm::dvec3& d1,
                   const CcdOptions& options = {}, CcdStats* stats = nullptr);

/// The two queries above with each corner's travel given, in the order p, a, b, c (vertex and
/// triangle) or a, b, c, d (two segments): mesh-level searches compute each vertex's once.
/// \pre travel[k] >= |x1_k - x0_k|; with glm::length(x1_k - x0_k) the answer is the one the
/// overloads above give.
bool ccd_vertex_triangle(const glm::dvec3& p0, const glm::dvec3& a0, const glm::dvec3& b0, const glm::dvec3& c0,
                         const glm::dvec3& p1, const glm::dvec3& a1, const glm::dvec3& b1, const glm::dvec3& c1,
                         const double travel[4], const CcdOptions& options, CcdStats* stats = nullptr);
bool ccd_edge_edge(const glm::dvec3& a0, const glm::dvec3& b0, const glm::dvec3& c0, const glm::dvec3& d0,
                   const glm::dvec3& a1, const glm::dvec3& b1, const glm::dvec3& c1, const glm::dvec3& d1,
                   const double travel[4], const CcdOptions& options, CcdStats* stats = nullptr);

enum class CcdKind : std::uint8_t {
  vertex_triangle,  ///< a vertex of the (first, moving) mesh against a triangle (of the second)
  triangle_vertex,  ///< a triangle of the first (moving) mesh against a vertex of the second
  edge_edge,        ///< an edge against an edge
};

/// One colliding pair.
/// - vertex_triangle: vertices = {vertex, corner0, corner1, corner2}; triangle = its id.
/// - triangle_vertex: vertices = {vertex, corner0, corner1, corner2}; triangle = its id.
/// - edge_edge: vertices = {e0, e1, f0, f1}, e0 < e1, f0 < f1; triangle = kNoTriangle.
/// For a mesh against itself all ids are of that mesh, (e0, e1) < (f0, f1), and the kind is
/// never triangle_vertex. Against a static mesh, the vertex of vertex_triangle and the
/// triangle of triangle_vertex and the edge (e0, e1) belong to the moving mesh; the rest to
/// the static one.
struct CcdPair {
  static constexpr std::uint32_t kNoTriangle = 0xffffffffu;
  CcdKind kind = CcdKind::vertex_triangle;
  std::array<std::uint32_t, 4> vertices{};
  std::uint32_t triangle = kNoTriangle;

  friend bool operator==(const CcdPair&, const CcdPair&) = default;
  friend auto operator<=>(const CcdPair&, const CcdPair&) = default;
};

struct StepCcdOptions {
  CcdOptions ccd;
  int threads = default_threads();  ///< worker threads (>= 1); the result does not depend on it
  /// find_step_collisions_with_static only: moving-mesh vertices flagged non-zero here (size =
  /// vertex count, or null for none) take part in no pair, nor do the moving triangles and
  /// edges that contain them. For vertices that rest on the static mesh by construction (the
  /// boundary of the fracture surface, projected onto the exterior), which would otherwise
  /// always be in contact.
  const std::vector<std::uint8_t>* ignored_vertices = nullptr;
  /// When true, pairs none of whose (moving-mesh) vertices changes position (x0 == x1) are not
  /// tested. Such a pair can only be reported when it is within the tolerance already at x0,
  /// and no choice of which vertices move changes that; skipping them makes a step in which few
  /// vertices move cost in proportion to those.
  bool skip_resting_pairs = false;
  /// When set (size = vertex count), only pairs with at least one (moving-mesh) vertex flagged
  /// non-zero here are tested; it then replaces skip_resting_pairs' rule. For repeated calls on
  /// one step where only the flagged vertices changed their end position since the last call:
  /// every other pair's answer is unchanged.
  const std::vector<std::uint8_t>* active_vertices = nullptr;
  /// find_step_collisions only: the mesh's unique edges (a < b), when the caller has them;
  /// null = derived from the triangles. \pre exactly the edges of `triangles`.
  const std::vector<std::array<std::uint32_t, 2>>* edges = nullptr;
  /// find_step_collisions only: when set, receives (sorted) every pair the broad phase and the
  /// narrow phase's distance filter with the corners' own travels let through (CcdStats::near),
  /// colliding or not: with the travels of this step no other pair can collide, nor can it after
  /// any vertices are sent back to x0.
  std::vector<CcdPair>* examined = nullptr;
  /// find_step_collisions only: when set, the broad phase and the distance filter are skipped
  /// and only these pairs are tested (those with an active vertex, as above). \pre `examined`
  /// of a call on the same x0 whose x1 differed only where vertices are now back at x0.
  const std::vector<CcdPair>* candidates = nullptr;
};

/// All colliding vertex-triangle and edge-edge pairs of a mesh against itself over the step
/// x0 -> x1, skipping pairs that share a vertex. Broad phase: AABB trees over the swept boxes
/// of triangles and edges (enlarged by min_distance), then the swept diagonal slabs of each pair
/// (slabs.hpp; apart only when the pair stays more than 4 (tolerance + min_distance) apart).
/// Sorted (kind, vertices, triangle).
/// \throw InputError when x0 and x1 differ in size, a coordinate is not finite, or a triangle
///        has an index out of range (the message names it).
std::vector<CcdPair> find_step_collisions(const std::vector<glm::dvec3>& x0, const std::vector<glm::dvec3>& x1,
                                          const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                          const StepCcdOptions& options = {});

/// A static mesh prepared once for repeated find_step_collisions_with_static calls: its used
/// vertices, unique edges and the three box trees (grown by `min_distance`).
struct StaticCcdMesh {
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::array<std::uint32_t, 1>> vertices;
  std::vector<std::array<std::uint32_t, 2>> edges;
  Bvh vertex_tree, triangle_tree, edge_tree;
  double min_distance = 0.0;
};

/// \throw InputError as find_step_collisions_with_static for the static mesh.
StaticCcdMesh prepare_static_ccd_mesh(const std::vector<glm::dvec3>& positions,
                                      const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                      double min_distance = 0.0, int threads = default_threads());

/// find_step_collisions_with_static against a prepared static mesh (same result).
/// \pre options.ccd.min_distance == prepared.min_distance.
std::vector<CcdPair> find_step_collisions_with_static(const std::vector<glm::dvec3>& x0,
                                                      const std::vector<glm::dvec3>& x1,
                                                      const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                      const StaticCcdMesh& prepared,
                                                      const StepCcdOptions& options = {});

/// All colliding pairs between a moving mesh (x0 -> x1, `triangles`) and a static mesh (for
/// example the exterior surface): moving vertices against static triangles, static vertices
/// against moving triangles, moving edges against static edges. Sorted. \throw as above, and
/// when options.ignored_vertices does not have one flag per moving vertex.
std::vector<CcdPair> find_step_collisions_with_static(const std::vector<glm::dvec3>& x0,
                                                      const std::vector<glm::dvec3>& x1,
                                                      const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                      const std::vector<glm::dvec3>& static_positions,
                                                      const std::vector<std::array<std::uint32_t, 3>>& static_triangles,
                                                      const StepCcdOptions& options = {});

}  // namespace fracref
