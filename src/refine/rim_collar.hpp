#pragma once
// The collar of S's rim: where S meets B at a grazing angle (its inner edges leave a rim vertex
// outward, along or above B's tangent plane there), S crosses B right next to the rim. Each such
// edge is split close to its rim end and the new vertex placed under B's tangent plane, so S
// bends into B at its rim: every face at the rim then starts inside B.
#include <cstddef>

#include "refine/topology_edit.hpp"
#include "rim/rim_on_b.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

struct CollarOptions {
  /// An inner edge is split when its direction rises above B's tangent plane at its rim end by
  /// more than -grazing (as a sine): grazing or outward.
  double grazing = 0.1;
  /// The new vertex goes this far along the edge, as a multiple of the rim vertex's shortest rim
  /// edge, at most a quarter of the edge.
  double reach = 1.0;
  /// and this far under the tangent plane, as a fraction of its distance from the rim vertex.
  double depth = 0.2;
  /// No split whose new vertex would lie closer than this fraction of the edge's length to the
  /// third corner of a face on the edge (it would make a needle there).
  double min_gap = 0.25;
  int passes = 8;  ///< rounds of splits (an edge split touches both its faces; one per face a round)
};

/// Splits the grazing inner edges at S's rim vertices (see the file comment); the tree records
/// each new vertex at its point on the edge. Returns the number of splits.
/// \pre s valid with adjacency current, rim locates every rim vertex of s, tree covers s.
std::size_t collar_rim(FractureSurface& s, RefinementTree& tree, const rim::ExteriorMesh& exterior, const rim::RimOnB& rim,
                       const CollarOptions& options = {});

}  // namespace fracref
