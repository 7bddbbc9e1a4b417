#pragma once
// Virtual fracture (paper section 4.1): cuts that do not separate are extended in their
// separation direction until every cut separates.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace fracref {

struct VirtualFractureStats {
  std::size_t faces_added = 0;  ///< faces newly cut
  double area_added = 0.0;      ///< their total area
};

/// Grows the set of cut faces of a tet mesh until no cut ends inside the material.
///
/// An edge is on the hull when a hull face uses it; every other edge of an interior face is
/// interior, and the faces around it close into a cycle (the tets around it). The crack front is
/// the interior edges with exactly ONE cut face around them: there the material on both sides of
/// the cut is still joined around the edge. (Two or more cut faces around an edge separate its
/// fan; a cut edge on the hull reaches the exterior.) At a front edge, the candidate is the uncut
/// face around it whose normal, wound consistently with the cut face across the edge, is closest
/// to the cut face's normal (largest dot product of unit normals; ties to the lowest face id).
/// While front edges remain, the best candidate over the whole front is cut (largest dot, then
/// lowest face id, then lowest edge), so the crack grows where it continues most smoothly first
/// and poorly aligned fronts are often closed by neighbouring growth. Each step cuts one face, so
/// this ends; deterministic.
///
/// \param positions  vertex positions (the ids of the faces index it)
/// \param interior_faces  faces shared by two tets (any winding), no two on the same vertex set
/// \param hull_faces  faces of one tet only
/// \param cut  per interior face, 1 when cut (inter-piece faces and cracks); updated in place
/// \throw RunError when cut has the wrong size or a face index is out of range.
VirtualFractureStats extend_cracks(const std::vector<glm::dvec3>& positions,
                                   const std::vector<glm::uvec3>& interior_faces,
                                   const std::vector<glm::uvec3>& hull_faces, std::vector<std::uint8_t>& cut);

}  // namespace fracref
