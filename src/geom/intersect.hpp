#pragma once
// Exact triangle-triangle intersection on the exact predicates, and the mesh-level
// "no two faces intersect except along shared edges" check.
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include "util/parallel.hpp"

namespace fracref {

using Triangle3 = std::array<glm::dvec3, 3>;
using TriangleIds = std::array<std::uint32_t, 3>;

/// Whether the closed segment [a,b] and the closed triangle t share a point. Exact.
/// Degenerate inputs are allowed (a == b, collinear or coincident triangle corners).
bool segment_triangle_intersect(const glm::dvec3& a, const glm::dvec3& b, const Triangle3& t);

/// Whether the closed segments [a,b] and [c,d] share a point. Exact; degenerate inputs allowed.
bool segments_intersect(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

/// Whether two closed triangles share at least one point (touching counts). Exact for every
/// input, including coplanar and degenerate (collinear or coincident corner) triangles.
bool triangles_intersect(const Triangle3& p, const Triangle3& q);

/// Whether faces `ti` and `tj` of a mesh intersect anywhere other than where the mesh connects
/// them, deciding by vertex ids (positions of distinct ids are never assumed equal):
/// - no shared id: triangles_intersect;
/// - one shared vertex s: true iff the closed triangles meet at a point other than s;
/// - a shared edge: true iff they meet outside that edge (coplanar and folded onto each other);
/// - the same three ids: true (a duplicated face).
/// Exact, degenerate faces included.
/// \pre every id < positions.size(); the three ids of each face are distinct.
bool mesh_faces_intersect(const std::vector<glm::dvec3>& positions, const TriangleIds& ti, const TriangleIds& tj);

struct SelfIntersectionOptions {
  std::size_t max_report = std::numeric_limits<std::size_t>::max();  ///< stop after this many
  int threads = default_threads();                                                    ///< worker threads (>= 1)
  /// Only pairs whose first face is below this index are looked for (faces from here on are
  /// only tested against the ones before: e.g. a fracture surface's faces followed by exterior
  /// faces that cannot meet each other).
  std::size_t query_faces = std::numeric_limits<std::size_t>::max();
};

/// The pairs (i, j), i < j and i < options.query_faces, of faces for which mesh_faces_intersect
/// holds, sorted, truncated to the first `max_report` in that order (so the answer does not
/// depend on `threads`).
/// Broad phase: an AABB tree over the face boxes (closed boxes, so touching faces are found).
/// \throw InputError when a face has an id out of range or a repeated id (names the face).
std::vector<std::pair<std::uint32_t, std::uint32_t>> find_self_intersections(
    const std::vector<glm::dvec3>& positions, const std::vector<TriangleIds>& triangles,
    const SelfIntersectionOptions& options);

/// find_self_intersections with default options and the given report limit.
std::vector<std::pair<std::uint32_t, std::uint32_t>> find_self_intersections(
    const std::vector<glm::dvec3>& positions, const std::vector<TriangleIds>& triangles, std::size_t max_report);

}  // namespace fracref
