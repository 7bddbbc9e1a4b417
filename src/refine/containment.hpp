#pragma once
// Tucking the fracture surface inside the exterior before the flow: the coarse fracture surface
// spans concave parts of B with flat faces that stick out of it, and the collision constraints
// of the flow can only keep S where it is, not bring it back in.
#include <cstddef>

#include "refine/exterior.hpp"
#include "refine/topology_edit.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

struct TuckOptions {
  double scale = 1.0;     ///< the length unit (bbox diagonal of B)
  double margin = 1e-3;   ///< a new vertex goes this far (· scale) inside B, at most
  int passes = 12;         ///< rounds of splits
  int sample_grid = 8;    ///< barycentric steps per side when looking for a face's part outside B
  double min_edge = 0.004;  ///< edges, and faces whose edges are all, shorter than twice this (· scale) are not split
};

/// Repeats up to `passes` times, each pass making the first of these kinds of splits that finds
/// any (one split per face or edge and pass):
/// 1. every interior edge of S with a sample outside B is split at its deepest one, the new
///    vertex at B's closest point moved inward along B's normal by min(margin · scale, a tenth
///    of the edge);
/// 2. every face that meets B (its corners on B pulled 2% of the way to its centroid, so a rim
///    face's own contact does not count) has the boundary edge whose chord reaches farthest out
///    of B (longer than 2 · min_edge · scale) split there, or when every chord is inside B its
///    longest boundary edge at the midpoint, the new vertex onto B;
/// 3. every face that meets B or whose centroid is outside B, and that has a sample point
///    outside B, is split 1-to-3 at its deepest outside sample, the new vertex placed as in 1
///    (inward by at most a fifth of the face's shortest edge).
/// Edges, and faces whose every edge is, no longer than 2 · min_edge · scale are not split (near a
/// concave corner of B the splits would otherwise pile up ever smaller faces). A split whose new
/// faces would meet another face of S is not made. The tree records each new
/// vertex at its sample point.
/// \return the number of splits made.
/// \pre s valid, tree covers every vertex of s.
std::size_t tuck_inside(FractureSurface& s, RefinementTree& tree, const ExteriorSurface& exterior,
                        const TuckOptions& options = {});

/// Splits every interior edge of S whose two ends lie on B (a chord: the pieces stage's
/// re-triangulation of B may join the same two vertices, and the piece would then have an edge
/// with four faces) at its midpoint, moved inside B by min(margin · scale, a tenth of the edge)
/// when it is outside or nearer to B than that; when the faces of that split would meet another
/// face of S, at the midpoint itself if it is inside B (the new faces then keep the old ones'
/// planes). Up to `passes` passes (each face split at most once per pass; a chord whose face was
/// split in a pass waits for the next), until a pass splits nothing; a split whose new faces would
/// meet another face of S is not made. Returns the number of splits. s is valid on return, its
/// adjacency rebuilt (rebuild_after_splits) when a split was made.
/// \pre s valid, tree covers every vertex of s.
std::size_t split_rim_chords(FractureSurface& s, RefinementTree& tree, const ExteriorSurface& exterior,
                             const TuckOptions& options = {}, int passes = 1);

/// Whether face f of S meets B away from its own corners on B (see tuck_inside).
bool face_meets_exterior(const FractureSurface& s, std::uint32_t f, const ExteriorSurface& exterior);

}  // namespace fracref
