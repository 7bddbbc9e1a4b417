#pragma once
// The five demo scenes and what they share. Not part of the public API.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenegen/scenegen_internal.hpp"

namespace fracref::scenegen_detail {

using Json = nlohmann::ordered_json;

inline constexpr int kFrames = 48;
inline constexpr double kFps = 24.0;

/// Where and how one scene is written.
struct SceneSetup {
  std::string name;
  std::filesystem::path folder;
  std::uint64_t seed = 1;
};

/// The scene JSON of scene `setup.name` (keys of scenes/SCHEMA.md): its title and comment,
/// `<name>.obj` as the exterior, `<name>_coarse.mesh` as the tets, `cracks` ("" = none), the
/// animation, the paper's field and grid, the scene's refine.tau and refine.delta, twice the
/// paper's refined count as the safety limit refine.max_triangles, and the seed as the field's and
/// the refiner's; weights, pyramid and the other refine keys keep their defaults.
Json scene_json(const SceneSetup& setup, const Json& animation, const std::string& cracks = "");

/// A labelled coarse tet mesh in material space.
struct PieceLayout {
  TetSet set;
  std::vector<int> labels;  ///< per tet, 0 .. pieces-1
  int pieces = 0;
  std::vector<glm::dvec3> centroids;  ///< per piece, volume-weighted
  std::vector<double> volumes;        ///< per piece
};

struct LayoutGoal {
  std::size_t target = 0;  ///< cut faces wanted
  int k_lo = 2, k_hi = 8;  ///< Voronoi sites tried
  std::size_t min_tets = 8;
  int cell_tets = 1;  ///< 6 keeps a box_lattice's cells whole (whole_cells)
  /// Per cell (cell_tets tets), the unit it belongs to: the cells of a unit keep one label
  /// (whole_units; the wall's bricks). Empty: no units.
  std::vector<int> units = {};
};

/// material_strength of the demo's own material (its field type, default parameters, the
/// setup's seed) on the object box [lo, hi].
/// \throw RunError when setup.name is no demo.
Strength demo_strength(const SceneSetup& setup, const glm::dvec3& lo, const glm::dvec3& hi);

/// weakness_cost(demo_strength(setup, lo, hi)): the crossing cost of the demo's own material.
CrackCost demo_weakness(const SceneSetup& setup, const glm::dvec3& lo, const glm::dvec3& hi);

/// best_layout on `set` with sites spread by `spacing` (local piece size, 1 = uniform); with
/// `weakness` (per-length crossing cost, weakness_cost), the cells are geodesic ones that meet
/// in weak material.
PieceLayout piece_layout(TetSet set, const LayoutGoal& goal, Rng& rng,
                         const std::function<double(const glm::dvec3&)>& spacing, const CrackCost& weakness = {});


/// The piece (label) whose tet centroid is nearest to `p`.
int piece_near(const PieceLayout& layout, const glm::dvec3& p);

/// Motion of a coarse vertex: (material position, group of Duplication::group, frame) -> position.
using Motion = std::function<glm::dvec3(const glm::dvec3&, int, int)>;

/// Writes kFrames text frames `<name>_frames/frame_NNNN.txt` (frame f holds the vertices whose
/// split frame is <= f, a prefix) and `<name>_frames/parents.txt`; returns the scene's
/// `animation` object.
Json write_frames_animation(const SceneSetup& setup, const TetSet& set, const Duplication& dup, const Motion& motion);

/// Writes `<name>_transforms.txt`; returns the scene's `animation` object.
Json write_rigid_animation(const SceneSetup& setup, const std::vector<std::vector<RigidTransform>>& frames);

Json make_bunny(const SceneSetup& setup, const std::filesystem::path& bunny_obj);
Json make_wall(const SceneSetup& setup);
Json make_branch(const SceneSetup& setup);
Json make_clay(const SceneSetup& setup);
Json make_jello(const SceneSetup& setup);

}  // namespace fracref::scenegen_detail
