#pragma once
// Smoothing the coarse rim on B before the flow (refine.rim_smoothing): a coarse fracture made of
// tetrahedra meets B along a zig-zag of B's edges, and the flow keeps the rim where it is, so
// the refined surface's outline would keep the tetrahedra's notches.
#include <cstddef>

#include "refine/exterior.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

struct RimSmoothingOptions {
  int passes = 0;                ///< rounds of smoothing; 0 = off
  double weight = 0.5;           ///< each pass moves a rim vertex this fraction of the way to its rim neighbours' mean
  double max_turn_degrees = 80.0;  ///< a face around a moved vertex may turn its normal by at most this
  double min_area_ratio = 0.2;   ///< ... and keep at least this fraction of its area
  double max_crease_degrees = 120.0;  ///< and no edge between two faces may bend further than this, unless it already did
  /// A move whose target lies farther off B than this fraction of its length is not made: the
  /// rim turns round a crease of B there, and the move would cut its corner.
  double max_off_b = 0.5;
};

/// Moves each rim vertex of S (a vertex on two or more boundary edges: inside a sheet's rim, or
/// a junction's end where sheets meet B together) the options.weight fraction of the way to the
/// mean of its rim neighbours, then to B's
/// closest point (unless that target lies off B by more than max_off_b of the move's length),
/// options.passes times (every vertex of a pass from the positions before it, so
/// the result does not depend on the order). A vertex stays where a face with a moved corner
/// would turn by more than max_turn_degrees, keep less than min_area_ratio of its area, or meet B
/// away from its corners on B where it did not (face_meets_exterior); where an edge between two
/// faces would bend past max_crease_degrees and further than it was; or where the motion would
/// collide with S (apply_collision_constraints), fold a face or reorder the sheets around a
/// junction edge (hold_folding_motion), make two faces that share a vertex cross
/// (hold_star_crossings), or bring two sheets' rims together on B (two rim edges that share no
/// vertex within a quarter of the shorter one, or two rim edges at a junction's end within 10°,
/// where they were farther apart). Held vertices are checked again until every check passes.
/// Connectivity does not change.
/// \pre s valid, its adjacency current, its boundary vertices on B, S free of self-intersections.
/// \return the number of vertex moves made, over all passes.
std::size_t smooth_rim(FractureSurface& s, const ExteriorSurface& exterior, const RimSmoothingOptions& options);

}  // namespace fracref
