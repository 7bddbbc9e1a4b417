#pragma once
// Edge collapses that remove the tips of junction hairpins: a junction curve of S that turns back
// on itself leaves a thin tongue of sheet whose tip the flow cannot draw back (every step that
// moves it folds its faces), and on the pieces it stands as a spike.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "surface/fracture_surface.hpp"

namespace fracref {

struct CollapseOptions {
  /// A junction vertex off B two of whose junction edges are closer than this (degrees) is a
  /// hairpin's tip; 0 = no collapses.
  double max_hairpin_degrees = 45.0;
  /// A face the collapse moves may turn by at most this (degrees), and not become degenerate.
  double max_turn_degrees = 30.0;
  /// When set, a collapse is not made when this holds for one of the faces it moves (the
  /// refiner's contact rule with B: refine/exterior_contact.hpp), given the faces' new corners.
  std::function<bool(const glm::uvec4& face)> reject_face;
};

/// Collapses each hairpin tip v into the nearer end u of its two junction edges closest in angle
/// (the farther one when the nearer is refused): the faces on edge v–u are removed and v's other faces take u in
/// v's place. v keeps its position and its entry in every per-vertex array but is left with no
/// face (so vertex ids, the refinement tree and the caller's per-vertex state stay valid); the
/// caller should not move it. A collapse is made only when it is checked, before it is made, to
/// keep S valid and free of self-intersections:
/// - neither v nor u lies on B;
/// - every vertex adjacent to both v and u is opposite edge v–u in a face (the link condition), and
///   every piece with faces at both v and u has a face on edge v–u (no piece is pinched);
/// - the faces around v and u, taken out with their neighbours' faces and collapsed, still make a
///   valid S at every edge the collapse changes (validate_edges: each piece closes up there, and
///   the sheets around each junction edge keep the pieces apart), with no two faces on one vertex
///   set and each piece's Euler characteristic unchanged;
/// - no moved face turns by more than max_turn_degrees or becomes degenerate, or meets another
///   face of S other than where S connects them (exact), or is refused by reject_face.
/// Collapses whose faces share a vertex are not made in the same call (the lower tip's first).
/// Rebuilds the adjacency when anything collapsed.
/// \pre s valid, its adjacency current, free of self-intersections.
/// \return the tips collapsed, ascending.
std::vector<std::uint32_t> collapse_hairpin_tips(FractureSurface& s, const CollapseOptions& options = {});

}  // namespace fracref
