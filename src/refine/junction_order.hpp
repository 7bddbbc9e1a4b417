#pragma once
// Whether an edge split keeps the order of the sheets around S's junction edges.
#include <glm/glm.hpp>

#include "refine/topology_edit.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

/// Whether splitting edge r.element at `at` keeps, around every junction (non-manifold) edge it
/// changes, the cyclic order of the faces that rebuild_adjacency reads from their geometry to
/// tell the pieces apart: around the split edge itself (its two halves, whose axis moves with the
/// rounding of `at`) and around the other junction edges of the faces it splits (whose opposite
/// vertex becomes `at`). A face whose opposite vertex lies within rounding of the junction's axis
/// can swap places with a neighbouring sheet then, and S would no longer be valid.
/// \pre adjacency current; r.kind == SplitRequest::kEdge.
bool split_keeps_junction_order(const FractureSurface& s, const SplitRequest& r, const glm::vec3& at);

}  // namespace fracref
