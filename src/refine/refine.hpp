#pragma once
// The refinement loop (paper 4.3–4.4): gradient flow of S in the modified strength field with
// boundary and collision constraints, adaptive splits (longest-edge bisection where a sample asks), and edge flips.
#include <cstdint>
#include <functional>
#include <vector>

#include "flow/backend.hpp"
#include "refine/exterior.hpp"
#include "rim/rim_on_b.hpp"
#include "refine/topology_edit.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

/// Parameters of refine_surface(); lengths are fractions of `scale` (the exterior's bbox diagonal).
struct RefineOptions {
  double scale = 1.0;           ///< the length unit of the fractions below (bbox diagonal of B)
  double tau = 0.002;           ///< split when a sample would move farther than tau·scale off its element
  double delta = 0.004;         ///< discard samples closer than delta·scale to a vertex
  /// Samples on S's rim (its edges on B) closer than max(delta, rim_delta)·scale to a vertex are
  /// discarded: the pieces stage traces each rim edge across B, and rim edges much shorter than
  /// B's own make its traces cross.
  double rim_delta = 0.001;
  /// The flow step's length: at the field's typical gradient (the root mean square of |∇ψ| over its
  /// nodes) a vertex is driven step·scale per iteration; 0 = the default (refine.cpp). The step is
  /// semi-implicit (flow/implicit_step.hpp), so it does not shrink with the triangles.
  double step = 0.0;
  /// Converged: E decreased by less than this fraction in each of two iterations in a row.
  double tolerance = 5e-4;
  int max_iterations = 200;               ///< a safety limit
  std::size_t max_triangles = 2000000;    ///< a safety limit: stop once a split would exceed it
  std::uint64_t seed = 1;
  double min_angle = 20.0;      ///< degrees: flip edges of faces with a smaller angle
  bool collisions = true;       ///< continuous collision detection of S against itself and B
  /// Let the flow slide S's rim (its vertices on B) along B; off, the rim stays where the coarse
  /// surface meets B and only its splits refine it (the pieces stage cannot yet cut B along a
  /// rim that wandered).
  bool rim_motion = false;
  /// Let a vertex inside a sheet move along S as well as across it (the full discrete gradient of
  /// equation 3); off, each moves along its normal only (motion_filters.hpp: for fields whose weak
  /// valleys are a grid cell or two wide).
  bool tangential_motion = true;
  /// Each flow step also moves every vertex inside a sheet this fraction of the way to its ring's
  /// centroid, along S (refine/relaxation.hpp), which evens the triangles out; it acts along S
  /// with tangential_motion off too. 0 = off (the paper's flow). In [0, 1].
  double relax = 0.0;
  /// Before the flow, this many passes of rim smoothing (refine/rim_smoothing.hpp) move each
  /// rim vertex along B half-way to its rim neighbours' midpoint, so the outline loses the coarse
  /// tetrahedra's zig-zag; 0 = off (the rim stays where the coarse surface meets B).
  int rim_smoothing = 0;
  /// Solves per flow step, in [1, 8]. Where the step would fold a face, the fold guard holds its
  /// corners where they are (refine/step_guard.hpp); with more than one solve, the step is then
  /// solved again with those vertices fixed, so their neighbours take the best motion around them
  /// instead of leaving a crease, until the guard holds nothing more or the solves run out (the
  /// guard still holds what the last one folds). 1 = one solve (the held vertices' neighbours
  /// move as if they had not been held, and fold into creases round them).
  int fold_solves = 2;
  /// Degrees: at the start of each iteration, a junction vertex whose junction curve turns back
  /// sharper than this (a hairpin's tip, which the flow cannot draw back without folding its
  /// faces) is collapsed into a neighbour on the curve (refine/collapses.hpp); 0 = off.
  double hairpin_collapse = 45.0;
};

/// What one iteration did (report.json's `iterations` list).
struct IterationStats {
  double energy = 0.0;              ///< E(S) after the iteration
  std::size_t triangles = 0;        ///< after the iteration
  double max_displacement = 0.0;    ///< largest vertex motion of the flow step (scene units)
  std::size_t collisions_stopped = 0;  ///< vertices held back by the collision constraints
  std::size_t splits = 0, flips = 0;
  std::size_t collapses = 0;  ///< hairpin tips collapsed (refine/collapses.hpp)
  double dt = 0.0;
  int solver_iterations = 0;  ///< conjugate-gradient iterations of the flow step's solve
  /// Whether the splits kept are the graded ones (longest-edge paths), not each on its sample's
  /// own element; and how many times the iteration was made (2: its graded splits were undone).
  bool graded = true;
  int attempts = 1;
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
  /// Where each rim vertex of the refined S lies on B; every rim edge lies in one triangle of B
  /// (the pieces stage cuts B along them).
  rim::RimOnB rim;
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
