#pragma once
// A section through the material: where the coarse and the refined cuts run against ζ (the
// paper's Figure 4 seen on a real scene). A person can see at a glance whether a refined cut
// follows weak material, and how far the weakest material lies from it.
#include <array>
#include <vector>

#include <glm/glm.hpp>

#include "field/grid.hpp"
#include "io/mesh_soup.hpp"
#include "preview/raster.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref {

/// An axis-aligned plane: the points whose coordinate `axis` is `at`.
struct SectionPlane {
  int axis = 0;
  double at = 0.0;
};

/// The segments where a triangle mesh meets the plane, each as its two end points.
/// A triangle with a corner exactly on the plane counts that corner on the positive side.
std::vector<std::array<glm::dvec3, 2>> section_segments(const std::vector<glm::dvec3>& positions,
                                                        const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                        const SectionPlane& plane);

/// Of the planes across the box [lo, hi] at 35%, 42.5%, 50%, 57.5% and 65% of it along each axis,
/// the one in which `s` is longest (the section that shows the most cut); ties go to the lower
/// axis, then to the plane nearer the middle.
SectionPlane best_section(const FractureSurface& s, const glm::dvec3& lo, const glm::dvec3& hi);

/// The section of the exterior's box along best_section(refined): ζ in the ramp of
/// StrengthRamp inside the exterior (the background outside it), a white line
/// where ζ crosses `weak_threshold` (the weakest quarter's edge, report.json
/// quality.weak_fraction.threshold), the exterior's outline in grey, the coarse cut dashed black
/// and the refined cut solid green. The plane's other two axes run right and up, in axis order;
/// fitted to `width` × `height` pixels.
/// \pre zeta covers the exterior's box; exterior has a triangle.
Image preview_section(const Grid3& zeta, double weak_threshold, const MeshSoup& exterior,
                      const FractureSurface& coarse, const FractureSurface& refined, int width = 1600,
                      int height = 1000);

}  // namespace fracref
