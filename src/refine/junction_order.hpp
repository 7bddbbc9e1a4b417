#pragma once
// Whether an edge split or an edge flip keeps the order of the sheets around S's junction edges.
#include <array>

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

/// Whether flipping regular edge e, whose quad flip_quad() found (opposite vertices `cd`, faces
/// `ff`: ff.x holds cd.x, ff.y holds cd.y), keeps the cyclic order of the faces around every
/// junction edge among the quad's four outer edges. The flip turns the quad's face on such an
/// edge to a new opposite vertex (cd.y on ff.x's outer edges, cd.x on ff.y's); a turn past
/// another sheet's face would make S invalid. `junctions` gets those outer junction edges
/// (kNoEdge in the unused places): a pass flips around each at most once, as each flip is judged
/// against the order before it.
/// \pre adjacency current.
bool flip_keeps_junction_order(const FractureSurface& s, std::uint32_t e, glm::uvec2 cd, glm::uvec2 ff,
                               std::array<std::uint32_t, 4>& junctions);

}  // namespace fracref
