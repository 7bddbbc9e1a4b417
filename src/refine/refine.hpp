#pragma once
// The refinement loop (paper 4.3–4.4): gradient flow of S in the modified strength field with
// boundary and collision constraints, adaptive 1-to-3 and edge splits, and edge flips.
#include <cstdint>
#include <functional>
#include <vector>

#include "flow/backend.hpp"
#include "refine/exterior.hpp"
#include "refine/topology_edit.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

/// Parameters of refine_surface(); lengths are fractions of `scale` (the exterior's bbox diagonal).
struct RefineOptions {
  double scale = 1.0;           ///< the length unit of the fractions below (bbox diagonal of B)
  double tau = 0.002;           ///< split when a sample would move farther than tau·scale off its element
  double delta = 0.004;         ///< discard samples closer than delta·scale to a vertex
  double step = 0.0;            ///< time step; 0 = automatic (see refine.cpp: median CFL rule)
  double tolerance = 1e-5;      ///< stop when the largest displacement < tolerance·scale and nothing split
  int max_iterations = 60;
  std::size_t max_triangles = 200000;  ///< stop once a split would exceed this many faces (the chord splits after the loop may add a few)
  /// Stop also once fewer than budget_slack·max_triangles faces are left to the budget: another
  /// iteration would add that little at the cost of an iteration at full size.
  double budget_slack = 0.1;
  /// When the next iteration, growing S as the current one does, would run into the budget, fill
  /// the budget now with the samples below tau (down to tau/4) that would move farthest, rather
  /// than in a last iteration that costs a pass over all of S for what is left (refine.cpp).
  bool fill_budget = true;
  std::uint64_t seed = 1;
  double min_angle = 20.0;      ///< degrees: flip edges of faces with a smaller angle
  bool collisions = true;       ///< continuous collision detection of S against itself and B
};

/// What one iteration did (report.json's `iterations` list).
struct IterationStats {
  double energy = 0.0;              ///< E(S) after the iteration
  std::size_t triangles = 0;        ///< after the iteration
  double max_displacement = 0.0;    ///< largest vertex motion of the flow step (scene units)
  std::size_t collisions_stopped = 0;  ///< vertices held back by the collision constraints
  std::size_t splits = 0, flips = 0;
  double dt = 0.0;
  double seconds = 0.0;  ///< wall-clock time of the iteration (splits, flips, flow step)
  /// Wall-clock seconds of the iteration's parts, in their order: the splits, the flips, the
  /// evaluation of the velocities after them, and the flow step (its collision constraints
  /// included, and also given alone).
  struct Phases {
    double splits = 0.0, flips = 0.0, evaluate = 0.0, flow = 0.0, flow_collisions = 0.0;
  } phases;
};

struct RefineResult {
  double initial_energy = 0.0;
  std::vector<IterationStats> iterations;
  RefinementTree tree;
  enum class Stop { kConverged, kTriangleBudget, kIterationCap } stop = Stop::kIterationCap;
};

/// Called after every iteration (for progress display); may be empty.
using RefineProgress = std::function<void(const IterationStats&, int iteration, int max_iterations)>;

/// Refines `s` in place. Every vertex of `s` present on entry is a leaf of the returned tree.
/// Deterministic for a given backend, options and input.
/// \throw RunError if the refined surface fails validate() (an internal error, never expected).
/// \pre s valid (validate(s) == ""), field covers B's bounding box, backend's field set or not
///      (refine_surface calls set_field itself).
RefineResult refine_surface(FractureSurface& s, const FieldGrid4& field, const ExteriorSurface& exterior,
                            ComputeBackend& backend, const RefineOptions& options,
                            const RefineProgress& progress = {});

}  // namespace fracref
