#pragma once
// What the refinement did to the fracture surface, in numbers a person can check against the
// pictures (report.json `quality`): how much the energy fell, how much of the surface lies in
// weak material, and how far the surface moved.
#include "field/field_sampler.hpp"
#include "field/grid.hpp"
#include "refine/exterior.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

struct SurfaceQuality {
  double coarse_energy = 0.0, refined_energy = 0.0;  ///< ∫ψ dA over each surface, finely sampled
  double energy_ratio = 0.0;                         ///< refined / coarse (0 when coarse is 0)
  double weak_threshold = 0.0;   ///< the 25th percentile of ζ over the grid nodes inside B
  double weak_coarse = 0.0, weak_refined = 0.0;  ///< area fraction with ζ below the threshold
  double displacement_mean = 0.0, displacement_p95 = 0.0, displacement_max = 0.0;  ///< ÷ diagonal
  /// weak_reach of the coarse surface at the refined surface's displacement_p95: how much of
  /// weak_refined a surface that close to the coarse one could have at most.
  double weak_reachable = 0.0;
  double weak_half_radius = 0.0;  ///< weak_reach's half_radius of the coarse surface (+inf past the search)
};

/// How much weak material (ζ < threshold) lies within reach of surface `s`.
struct WeakReach {
  double fraction = 0.0;     ///< area fraction whose normal line meets weak material within ±radius
  double half_radius = 0.0;  ///< the smallest radius at which `fraction` would reach 1/2 (÷ diagonal); +inf past max
};

/// For each of `s`'s area samples (those of measure_quality, at most 16² a face), the distance
/// along its face's normal, either way, to the nearest point with ζ < threshold, stepped at half
/// of ζ's cell (or max_radius × diagonal / 128 when that is longer) up to `max_radius` × diagonal.
/// A surface that stays within `radius` × diagonal of `s`, each point along `s`'s normal there,
/// can have at most `fraction` of its area in weak material: an upper bound on what refining `s`
/// that little can reach (points outside B count, as if material were there).
/// \pre radius and max_radius >= 0 and finite; zeta covers s.
WeakReach weak_reach(const FractureSurface& s, const Grid3& zeta, double threshold, double radius, double diagonal,
                     double max_radius = 0.25);

/// Measures the coarse and the refined surface with the same ψ (`field`'s value channel) and ζ.
/// Each face is cut into n² equal triangles with n = ⌈longest edge / grid cell⌉ and sampled at
/// their centroids, so every grid cell of area gets a sample. The displacement is each refined
/// vertex's distance from the coarse surface, weighted by a third of its faces' area.
/// \pre coarse has a face; zeta and field cover B's box.
SurfaceQuality measure_quality(const FractureSurface& coarse, const FractureSurface& refined, const FieldGrid4& field,
                               const Grid3& zeta, const ExteriorSurface& exterior);

}  // namespace fracref
