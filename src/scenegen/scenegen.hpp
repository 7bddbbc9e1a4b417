#pragma once
// The paper's five scenes (its section 6) as generated inputs: every file a user would give
// fracref - the exterior mesh (OBJ), the coarse labelled tetrahedral mesh (MEDIT .mesh), an
// optional cracks file, the coarse animation (frame files + parent map, or rigid transforms) -
// and a scene JSON referencing them with relative paths. The coarse fracture is made as a
// simulator would leave it, with its hull vertices on the exterior:
//  - bunny: isosurface stuffing of the npm bunny on a Kuhn lattice (a tenth of its size per
//    cube), seeded Voronoi pieces laid out by the material (below); rigid pieces that burst
//    apart and fall;
//  - branch: a structured cylinder, ONE labelled piece and a cracks file covering the middle
//    cross-section above a (seeded) front at y in [-0.4, -0.2], completed by virtual fracture;
//    frames that bend it, then open the crack about its front (backward remeshing: the crack's
//    duplicated vertices appear at frame 20);
//  - wall: a lattice of half bricks (its planes in the middle of the mortar joints), Voronoi
//    pieces of whole cells, smaller near the wrecking ball's impact; rigid pieces knocked out and
//    falling, the rest standing;
//  - clay: a box lattice mapped onto a rounded box, Voronoi pieces; frames twisting it about its
//    long axis, the pieces tearing off late (frames 30-44);
//  - jello: a box lattice, Voronoi pieces; frames bouncing it with squash and stretch, the
//    pieces breaking off one by one (frames 14-44).
// The Voronoi cells (all but the branch's) are geodesic ones under a crossing cost that is high
// in weak material, so that the cracks run where the scene's material is weak, as a coarse
// simulation of it would crack (docs/DESIGN.md, "Where the demos' coarse cracks run").
// The number of Voronoi sites is chosen so that the coarse fracture surface has about the
// paper's triangle count (demo_scene_targets()); a piece layout is cleaned so that every piece
// is a connected 2-manifold solid and every cut meets the exterior in one face per hull edge.
//
// Deterministic: the same name, options and build give the same files byte for byte (numbers
// are written in their shortest round-trip form).
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

/// The paper's numbers for one scene (docs/DESIGN.md, "The paper's scenes").
struct DemoTarget {
  std::string name;
  std::size_t coarse_triangles = 0;   ///< triangles of the coarse fracture surface
  std::size_t refined_triangles = 0;  ///< the paper's refined count (twice it is the scene's refine.max_triangles)
  double seconds = 0.0;               ///< the paper's refinement time (one i7-2600 core, 2014)
};

/// {"bunny", "branch", "wall", "clay", "jello"}, the order of the paper.
std::vector<std::string> demo_scene_names();

/// The paper's coarse and refined triangle counts and time, one per demo_scene_names() entry.
std::vector<DemoTarget> demo_scene_targets();

/// Writes the demo scene `name` into `folder` (created if missing; files of the same names are
/// replaced, other files are left alone, so all five fit in one folder) and returns the path of
/// its scene file, `folder/<name>.json`. Files written (paths in the scene are relative):
///   <name>.obj (the exterior; bunny.obj is a byte copy of options.bunny_obj),
///   <name>_coarse.mesh, branch_cracks.txt (branch only),
///   frames scenes (branch, clay, jello): <name>_frames/frame_0000.txt .. frame_0047.txt and
///   <name>_frames/parents.txt; rigid scenes (bunny, wall): <name>_transforms.txt.
/// 48 frames at 24 fps. The field's and the refiner's seeds are options.seed.
/// The scene loads with load_scene + load_tet_model + load_frames / load_rigid.
/// \throw InputError for an unknown name (listing the known ones), and for bunny when
///        options.bunny_obj is empty, missing or not a closed mesh (naming the file).
/// \throw RunError when a file cannot be written.
std::filesystem::path generate_demo_scene(const std::string& name, const std::filesystem::path& folder,
                                          const DemoOptions& options = {});

}  // namespace fracref
