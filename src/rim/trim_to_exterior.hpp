#pragma once
// S trimmed to B (issue 29): where the coarse S leaves B (it meets B at a grazing angle, or
// overshoots a concave part), every face of S is cut along its intersection with B's triangles
// and only the parts inside B are kept, so that S lies inside B before the flow starts and the
// contact rule (refine/exterior_contact.hpp) can keep it there.
#include <cstdint>
#include <vector>

#include "rim/rim_on_b.hpp"

namespace fracref::rim {


/// Cuts S along S ∩ B and drops the parts outside B. Intersections are decided with exact
/// orient3d predicates on S's positions (a rim vertex at its location's point, counted as on every
/// triangle of B that holds it: a rim edge is not an intersection, nor a face's touching B at its
/// own rim vertex), points are computed in double:
/// - where an S edge crosses a B triangle T, one vertex per (edge, T), shared by the faces on the
///   edge, located in T (barycentric weights), recorded as the 2-parent point of the edge; where
///   it passes exactly through a B edge or vertex (orient3d zero), one vertex per (edge, that B
///   edge or vertex), located there and shared by the triangles around it;
/// - where a B edge crosses the interior of a face F, one vertex per (B edge, F), located on the
///   B edge, recorded as the 3-parent barycentric point of F.
/// The segments F ∩ T (one per face and B triangle, each in T) are constraints of a constrained
/// triangulation of F in its barycentric plane (rim/cut_triangulation.hpp); the resulting pieces of
/// all faces are joined into regions across the edges that are not segments, and each region is
/// kept or dropped by the side of B's plane its triangles lie on next to the segments and rim
/// edges that bound it (exact orient3d of a triangle's centroid; majority, ties by
/// point_in_mesh). The kept faces keep their pieces and winding; the new vertices are appended
/// (their weights in `added`, their locations in `rim`); the adjacency is rebuilt. Every new rim
/// edge is a segment F ∩ T, in one triangle of B.
/// A rim edge that lies in no one triangle of B (a chord of B that embed_rim has not traced yet)
/// is an edge of S like any other there: cut where it crosses B, its ends on B counted as on every
/// triangle that holds them.
/// \pre s's adjacency current; rim covers s's vertices.
/// \throw RunError naming the face when the intersection is degenerate (a segment with one end,
///        or more than two ends), a face cannot be triangulated along its segments, or the result
///        is not a valid S.
TrimStats trim_to_exterior(FractureSurface& s, const ExteriorMesh& m, RimOnB& rim, std::vector<EmbeddedVertex>& added);

}  // namespace fracref::rim
