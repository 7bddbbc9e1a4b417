#pragma once
// Tet labellings for the `cuts` input: the pieces a crack set makes, and the clean-up that makes
// a labelling one whose label boundaries form a valid fracture surface S (cuts_model.cpp).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "coarse/tet_lattice.hpp"

namespace fracref {

/// Per tet, the lowest tet of its component once the cracked faces are removed: tets joined by
/// an uncracked interior face share a label.
/// \pre cracked.size() == faces.faces.size(), faces = interior_faces(set).
/// \throw RunError when the sizes differ.
std::vector<std::uint32_t> crack_components(const TetSet& set, const InteriorFaces& faces,
                                            const std::vector<std::uint8_t>& cracked);

struct FanCleanupOptions {
  /// Passes over the edges; each pass fixes every bad fan it meets with the labels of that moment.
  int max_passes = 16;
};

struct FanCleanupStats {
  std::size_t tets_moved = 0;  ///< tets whose label was changed (counted once per change)
  int passes = 0;              ///< passes made, the last one finding nothing bad when `clean`
  bool clean = false;          ///< no bad fan is left
};

/// Relabels tets so that S, the faces between different labels, is one the fracture surface can
/// represent at every edge of the tet mesh. Around an edge the tets form a fan: a cycle for an
/// interior edge, a path from hull face to hull face for an edge on the hull. The fan splits into
/// wedges (maximal runs of one label). A fan is bad when
///   - on the hull, it has three or more wedges: S would have two or more faces at an edge of B,
///     where it may have one (the middle wedges touch B along the edge only);
///   - inside, a label holds two or more wedges: that piece would touch itself along the edge.
/// Both come from a lattice too coarse for the geometry there (a cut grazing B, a thin part).
/// Labels are ranked once, by their total volume (ties to the lower label). A bad fan is fixed
/// by relabelling its smallest offending wedge (by volume; ties to the first in fan order) that
/// has a neighbouring wedge of a higher-ranked label, with the label of the larger such
/// neighbour, until the fan is good; each move merges two wedges, and a tet's label only rises
/// in rank, so this ends. Edges are visited in ascending (a, b) order, pass after pass, until a
/// pass changes nothing or max_passes is reached. Deterministic. A piece whose tets are all
/// moved disappears.
/// \pre labels.size() == set.tets.size(), each label a tet id (as crack_components() gives);
///      set's tets positively oriented and conforming.
/// \throw RunError when the sizes differ or a label is not a tet id.
FanCleanupStats clean_label_fans(const TetSet& set, std::vector<std::uint32_t>& labels,
                                 const FanCleanupOptions& options = {});

}  // namespace fracref
