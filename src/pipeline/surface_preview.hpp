#pragma once
// Pictures of the fracture surface coloured by the material strength ζ.
#include <glm/glm.hpp>

#include "field/grid.hpp"
#include "preview/raster.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

/// ζ's colour: a ramp from dark purple (weak) through red and orange to pale yellow (strong),
/// `t` ζ normalised to [0, 1] by the grid's range.
glm::vec3 strength_color(double t);

/// ζ at p normalised to [0, 1] by the range of ζ over its grid (0.5 for a constant grid).
double normalized_strength(const Grid3& zeta, const glm::dvec3& p);

/// The fracture surface alone, each face coloured by ζ at its centroid, seen along the candidate
/// direction (the 3 axes and the 4 diagonals, both ways) in which its projected area is largest.
/// `width` × `height` pixels.
Image preview_strength_surface(const FractureSurface& s, const Grid3& zeta, int width = 1600, int height = 1000);

}  // namespace fracref
