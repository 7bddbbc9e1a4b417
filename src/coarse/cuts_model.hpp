#pragma once
// The `cuts` coarse input (scene `fracture.kind: "cuts"`): a closed exterior B plus open,
// artist-drawn cut surfaces inside it, possibly not reaching B. They become a labelled tet mesh
// whose cracks follow the cuts, then a CoarseModel through build_tet_model() with virtual
// fracture completing the cuts that do not separate (paper 4.1). Rule documented in
// scenes/INPUTS.md, "Exterior plus cuts".
#include <filesystem>
#include <string>

#include "coarse/coarse_model.hpp"
#include "io/mesh_soup.hpp"

namespace fracref {

struct CutsOptions {
  /// Lattice cell = the exterior's bounding-box diagonal / this.
  double cells_per_diagonal = 24.0;
  /// Isosurface stuffing: a lattice vertex closer to B than this fraction of an edge snaps onto B.
  double warp = 0.3;
  /// Extend the cracks until every cut separates; when false a non-separating cut is an error.
  bool virtual_fracture = true;
};

/// Builds the coarse model: B's inside is filled with tets (isosurface stuffing on a Kuhn lattice
/// of cell diag/cells_per_diagonal), all one piece; an interior face is a crack when the segment
/// between the centroids of its two tets crosses a cut triangle; build_tet_model() then makes
/// the pieces (extending the cracks by virtual fracture, reported in virtual_area_added).
/// \pre `exterior` is closed, manifold and outward (the pipeline checks it with make_exterior).
/// \throw InputError naming `cuts_file` when it has no triangle, or when a cut (a connected
///        part of its triangles) crosses no tet face inside B (it lies outside B, or is smaller
///        than the lattice cell); and as build_tet_model() (a cut that cannot separate).
CoarseModel build_cuts_model(const MeshSoup& exterior, const MeshSoup& cuts, const std::string& cuts_file,
                             const CutsOptions& options = {});

/// Reads both meshes (OBJ, OFF or PLY) and calls build_cuts_model().
/// \throw InputError as the mesh readers and build_cuts_model().
CoarseModel load_cuts_model(const std::filesystem::path& exterior, const std::filesystem::path& cuts,
                            const CutsOptions& options = {});

}  // namespace fracref
