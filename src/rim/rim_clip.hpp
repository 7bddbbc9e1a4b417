#pragma once
// Internal to the rim room: S clipped to B where it meets B at a grazing angle (rim_on_b.hpp).
#include <cstdint>
#include <vector>

#include "rim/rim_on_b.hpp"

namespace fracref::rim {

/// A rim vertex is grazing when a face at it has a vertex off the rim that does not lie strictly
/// inside B's side of the plane of a triangle of B holding the rim vertex's location: that face
/// leaves the rim above B and crosses it. Every face at a grazing rim vertex p that has a corner
/// inside B is cut where S enters B: each of its edges from a corner inside B to p is cut where
/// it first meets B going toward p (moved out along B's normal so that it does meet B), and the
/// cut points are joined across B along the curve where the face's plane meets B (the trace:
/// new rim vertices on B's edges). The part of the face inside is triangulated in its plane;
/// p is left unused. Faces without a corner inside B are kept. Vertices are appended (recorded
/// in `added` with their rest-pose weights on the face's corners), faces replaced in place or
/// appended; the caller rebuilds the adjacency.
/// \pre s's adjacency current; rim locates every rim vertex of s.
/// \return the number of rim vertices clipped away.
std::uint32_t clip_grazing_rim(FractureSurface& s, const ExteriorMesh& m, RimOnB& rim, std::vector<EmbeddedVertex>& added,
                               const EmbedOptions& options);

}  // namespace fracref::rim
