#pragma once
// Clean-ups of a labelling of a tet mesh's tets before build_tet_model() makes S from it (used by
// the fit of pieces that nearly conform, pieces_fit.cpp): stray islands of a label, and edges S
// cannot represent (through clean_label_fans() of the cuts input).
#include <cstddef>
#include <vector>

#include "coarse/tet_lattice.hpp"

namespace fracref::coarse_detail {

/// Gives each face-connected part of a label other than its largest, with at most `fraction` of
/// the largest part's tets, to the label it shares most faces with (ties to the lower label);
/// repeated while anything changes, 8 rounds at most. Returns the tets moved.
/// \pre label.size() == tets; faces = interior_faces() of the mesh.
std::size_t merge_islands(std::size_t tets, const InteriorFaces& faces, std::vector<int>& label, double fraction);

/// Gives each tet off the hull whose four neighbours across its faces include three or four of
/// one other label that label: a lattice tet sticking into a neighbour's side, or a notch of one
/// missing from it, whose faces would make S a zig-zag of creases where the pieces' common face is
/// flat (Blender's Cell Fracture cuts the lattice at every angle). One round, from the labels
/// before it. Returns the tets moved. \pre label.size() == tets; faces = interior_faces().
std::size_t relabel_notches(std::size_t tets, const InteriorFaces& faces, std::vector<int>& label);

/// clean_label_fans() (cut_labels.hpp) on labels that are piece numbers: relabels the wedges of
/// tets S could not represent at an edge (three pieces at an edge of the hull, a piece touching
/// itself along an edge). Returns the tets moved. \pre labels >= 0, label.size() == set.tets.size().
std::size_t clean_fans(const TetSet& set, std::vector<int>& label);

/// Per tet, whether every tet sharing a corner with it has its label and no corner lies on the
/// hull: a tet given another label there makes no edge S cannot represent.
std::vector<bool> deep_in_one_label(const TetSet& set, const std::vector<int>& label);

}  // namespace fracref::coarse_detail
