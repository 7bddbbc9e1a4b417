#pragma once
// Pictures of the fracture surface coloured by the material strength ζ.
#include <array>
#include <functional>

#include <glm/glm.hpp>

#include "field/grid.hpp"
#include "preview/raster.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

/// Faces bent further apart than this (degrees) are lit apart in the previews; gentler bends are
/// lit smoothly (smooth_corner_normals), so a curved surface made of flat triangles reads as curved.
constexpr double kPreviewCrease = 45.0;

/// A piece's colour where no material colours its faces (a palette of 8, repeating).
glm::vec3 piece_color(int piece);

/// ζ's colours: a ramp from dark purple (weak) through red and orange to pale yellow (strong)
/// over the range of ζ on its grid (found once; the middle colour for a constant grid).
class StrengthRamp {
 public:
  /// \pre `zeta` outlives the ramp.
  explicit StrengthRamp(const Grid3& zeta);
  /// The colour of ζ at p.
  glm::vec3 at(const glm::dvec3& p) const;

 private:
  const Grid3& zeta_;
  double lo_ = 0.0, range_ = 0.0;
};

/// A fracture face's colour at a material-space point.
using FractureColour = std::function<glm::vec3(const glm::dvec3& material_position)>;

/// The material's own colours (`albedo`: sample_albedo's three channels, trilinear, clamped to
/// [0, 1]) when given, else ζ's ramp. The result refers to both.
FractureColour fracture_colour(const std::array<Grid3, 3>* albedo, const StrengthRamp& ramp);

/// `view` (unit), turned 0.6 rad towards the side that most of the walls face when walls are
/// 5% to 30% of the area: faces turned over 60 degrees from `view`, which would be seen edge-on
/// (the steps of a splintered break), and the faces look at the view on the whole (the mean
/// |cos| of their angle to it, by area, is 0.75 or more). `normals`: the faces' normals, each as
/// long as its face's area.
glm::dvec3 towards_walls(const std::vector<glm::dvec3>& normals, const glm::dvec3& view);

/// The fracture surface alone, coloured by ζ at each pixel's point of it and lit smoothly, seen along the candidate
/// direction (the 3 axes and the 4 diagonals, both ways) that shows it best: the most pixels
/// covered (fitted to the frame) times the fraction of its area not seen edge-on; then turned
/// towards its walls (towards_walls). `width` × `height` pixels.
Image preview_strength_surface(const FractureSurface& s, const Grid3& zeta, int width = 1600, int height = 1000);

}  // namespace fracref
