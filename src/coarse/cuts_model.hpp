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
  /// Lattice cell = the exterior's bounding-box diagonal / this. 0 = automatic: auto_cells_first,
  /// doubled while a cut cracks no face, up to auto_cells_max.
  double cells_per_diagonal = 0.0;
  double auto_cells_first = 24.0;
  double auto_cells_max = 96.0;
  /// Isosurface stuffing: a lattice vertex closer to B than this fraction of an edge snaps onto B.
  double warp = 0.3;
  /// Extend the cracks until every cut separates; when false a non-separating cut is an error.
  bool virtual_fracture = true;
};

/// Builds the coarse model:
///  1. B's inside is filled with tets (isosurface stuffing on a Kuhn lattice of cell
///     diag/cells_per_diagonal; automatic: the coarsest of 24, 48, 96 at which B holds a tet
///     and every cut cracks a face);
///  2. an interior face is a crack when the segment between the centroids of its two tets
///     crosses a cut triangle, so a cut reaching past B is clipped to B;
///  3. with virtual_fracture the cracks are extended until they separate (extend_cracks());
///  4. the tets are labelled by the components the cracks leave, and clean_label_fans() relabels
///     the wedges S could not represent (a cut grazing B, a thin part);
///  5. build_tet_model() makes the pieces and S from the labels (virtual fracture stats summed).
/// \pre `exterior` is closed, manifold and outward (the pipeline checks it with make_exterior).
/// \throw InputError naming `cuts_file` when it has no triangle, or when a cut (a connected
///        part of its triangles) crosses no tet face inside B at the finest lattice allowed (it
///        lies outside B, or is smaller than the lattice cell), or when no tet fits inside B;
///        when a cut separates nothing even after virtual fracture (it goes around a handle);
///        and as build_tet_model() (with virtual_fracture off, a cut that does not separate).
/// \throw RunError "internal error in the cuts input: ..." when S is still invalid (a bug).
CoarseModel build_cuts_model(const MeshSoup& exterior, const MeshSoup& cuts, const std::string& cuts_file,
                             const CutsOptions& options = {});

/// Reads both meshes (OBJ, OFF or PLY) and calls build_cuts_model().
/// \throw InputError as the mesh readers and build_cuts_model().
CoarseModel load_cuts_model(const std::filesystem::path& exterior, const std::filesystem::path& cuts,
                            const CutsOptions& options = {});

}  // namespace fracref
