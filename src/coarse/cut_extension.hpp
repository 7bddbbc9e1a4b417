#pragma once
// Virtual fracture for flat cuts of the `cuts` input: a flat cut that stops inside B (a disc) is
// extended in its own plane until it meets B, instead of by the face-by-face growth of
// extend_cracks(), whose greedy steps on a tet lattice wander off an oblique plane and close
// pockets (one disc became 8 pieces). Only flat cuts: the plane of a bent sheet crosses the sheet
// again and again, and would cut many pieces.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "coarse/tet_lattice.hpp"
#include "io/mesh_soup.hpp"

namespace fracref {

/// A cut's best-fit plane.
struct CutPlane {
  glm::dvec3 point{0.0};   ///< area-weighted centroid of the cut's triangles
  glm::dvec3 normal{0.0};  ///< unit; area-weighted mean of the triangle normals, each turned to agree with the first
  bool flat = false;       ///< every vertex within `flatness` × the cut's bounding-box diagonal of the plane
};

struct PlaneOptions {
  double flatness = 0.002;  ///< a sheet bent more (a wavy sheet) is left to extend_cracks(): its plane would cross it again and again
};

/// The plane of each cut (triangles `part[t]` = c for cut c, c < parts).
/// \pre part.size() == cuts.triangles.size(), every part < parts.
std::vector<CutPlane> cut_planes(const MeshSoup& cuts, const std::vector<std::uint32_t>& part, std::uint32_t parts,
                                 const PlaneOptions& options = {});

struct PlaneExtensionStats {
  std::size_t faces_added = 0;
  double area_added = 0.0;
};

/// For each flat cut c, cracks every interior face that its plane crosses (the segment between
/// the centroids of the face's two tets has one end on or below the plane, the other above) and
/// that is connected to a face cut c cracked (face_cut[f] == c) through such faces sharing an
/// edge. The plane's crossed faces around B's inside bound the tets on its two sides, so the
/// result is the cut grown in its plane until it meets B (or other parts of B's inside that the
/// plane reaches through the same component). Breadth-first from the cut's faces in ascending
/// order; deterministic.
/// \pre faces = interior_faces(set); cracked and face_cut have one entry per interior face.
/// \throw RunError when the sizes differ.
PlaneExtensionStats extend_in_planes(const TetSet& set, const InteriorFaces& faces, const std::vector<CutPlane>& planes,
                                     const std::vector<std::uint32_t>& face_cut, std::vector<std::uint8_t>& cracked);

}  // namespace fracref
