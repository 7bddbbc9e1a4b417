#pragma once
// The paper's five scenes (its section 6) as generated inputs: every file a user would give
// fracref - the exterior mesh (OBJ), the coarse labelled tetrahedral mesh (MEDIT .mesh), an
// optional cracks file, the coarse animation (frame files + parent map, or rigid transforms) -
// and a scene JSON referencing them with relative paths. The coarse fracture is made as a
// simulator would leave it: a cube-split (Freudenthal) lattice over the exterior's box, tets kept
// by centroid inside the exterior, hull vertices projected onto it, pieces labelled by seeded
// Voronoi cells (or a planar crack for the branch), sized so that the coarse fracture surface has
// about the paper's triangle count (demo_scene_targets()).
//
// Deterministic: the same name, options and build give the same files byte for byte.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace fracref {

struct DemoOptions {
  /// The Stanford bunny (npm bunny@1.0.1 converted to OBJ: 1,839 vertices, 3,674 triangles,
  /// y up). Needed by "bunny" only; it is copied into the folder.
  std::filesystem::path bunny_obj;
  /// Seed of the piece layout, the animation and the scene's field and refine seeds.
  std::uint64_t seed = 1;
};

/// The paper's numbers for one scene (DESIGN.md, "The paper's scenes").
struct DemoTarget {
  std::string name;
  std::size_t coarse_triangles = 0;   ///< triangles of the coarse fracture surface
  std::size_t refined_triangles = 0;  ///< the scene's refine.max_triangles
};

/// {"bunny", "branch", "wall", "clay", "jello"}, the order of the paper.
std::vector<std::string> demo_scene_names();

/// The paper's coarse and refined triangle counts, one per demo_scene_names() entry.
std::vector<DemoTarget> demo_scene_targets();

/// Writes the demo scene `name` into `folder` (created if missing; files of the same names are
/// replaced, other files are left alone) and returns the path of its scene file,
/// `folder/<name>.json`. Files written (paths in the scene are relative to `folder`):
///   <name>.obj (exterior; bunny.obj is a copy of options.bunny_obj), <name>_coarse.mesh,
///   branch only: branch_cracks.txt; frames scenes (branch, clay, jello): frames/frame_NNNN.txt
///   (48 frames) and frames/parents.txt; rigid scenes (bunny, wall): <name>_transforms.txt.
/// The scene loads with load_scene + load_tet_model + load_frames / load_rigid.
/// \throw InputError for an unknown name (listing the known ones), and for bunny when
///        options.bunny_obj is empty, missing or not a closed mesh (naming the file).
/// \throw RunError when a file cannot be written.
std::filesystem::path generate_demo_scene(const std::string& name, const std::filesystem::path& folder,
                                          const DemoOptions& options = {});

}  // namespace fracref
