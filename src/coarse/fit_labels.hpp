#pragma once
// Clean-ups of a labelling of a tet mesh's tets before build_tet_model() makes S from it (used by
// the fit of pieces that nearly conform, pieces_fit.cpp): stray islands of a label, and edges S
// cannot represent: a piece touching itself along an edge, three pieces meeting at an edge of the
// hull (S's side components would join two of them across the outside of the mesh).
#include <cstddef>
#include <vector>

#include "coarse/tet_lattice.hpp"

namespace fracref::coarse_detail {

/// Gives each face-connected part of a label other than its largest, with at most `fraction` of
/// the largest part's tets, to the label it shares most faces with (ties to the lower label);
/// repeated while anything changes, 8 rounds at most. Returns the tets moved.
/// \pre label.size() == tets; faces = interior_faces() of the mesh.
std::size_t merge_islands(std::size_t tets, const InteriorFaces& faces, std::vector<int>& label, double fraction);

/// Makes every edge one S can represent: around each edge (its tets in order, a closed fan
/// inside the mesh, an open one on its hull) each label holds one run of tets, and at most two
/// labels meet at a hull edge (where S meets the exterior). A bad run takes the higher label of a
/// neighbouring run, or a neighbouring run takes the bad run's higher label, whichever moves
/// fewer tets; labels only grow, so the repair ends. Tets marked in `locked` keep their label.
/// Repeated over every edge while anything changes (64 rounds at most). Returns the tets relabelled.
/// \pre label.size() == locked.size() == set.tets.size(); set's tets conform.
std::size_t untangle_edges(const TetSet& set, std::vector<int>& label, const std::vector<bool>& locked);

/// Per tet, whether a corner lies on the mesh's hull (a face of one tet).
std::vector<bool> touches_hull(const TetSet& set);

}  // namespace fracref::coarse_detail
