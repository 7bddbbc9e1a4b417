#pragma once
// A convex prism around the tetrahedron of a nearly flat quad (or a triangle, a corner repeated),
// optionally grown: a cheap, conservative test that a triangle cannot meet anything inside it (an
// edge flip's new faces; a split's new faces within a reach of the faces they replace).
#include <array>

#include <glm/glm.hpp>

namespace fracref {

/// The prism bounded by two planes across `normal` (at the corners' lowest and highest heights)
/// and, for each side (p[k], p[k+1]) of the quad p[0], p[1], p[2], p[3] (in order around it as
/// seen along `normal`), a plane through that side parallel to `normal`. A side plane the four
/// corners do not all lie behind (a quad that is not convex seen along `normal`) is left out, so
/// the prism always holds the tetrahedron conv(p). With `grow` > 0 every plane is moved out by it,
/// so the prism holds every point within `grow` of conv(p). A triangle is the quad p0, p1, p2, p2.
class QuadPrism {
 public:
  /// \pre normal != 0; finite corners; grow >= 0.
  QuadPrism(const std::array<glm::dvec3, 4>& p, const glm::dvec3& normal, double grow = 0.0);

  /// True only if triangle g meets conv(p) nowhere but at its corners that are quad corners:
  /// corner k of g is quad corner shared[k] (0..3), or not one (-1). Decided in floating point
  /// with margins far above its rounding (a triangle it cannot place is not separated), by a plane
  /// of the prism that g lies beyond; for one shared corner, a side plane through that corner.
  /// Two or three shared corners, or any shared corner of a grown prism: never separated.
  bool separates(const std::array<glm::dvec3, 3>& g, const std::array<int, 3>& shared) const;

  /// True only if the box [lo, hi] lies beyond one of the prism's planes by the margin that
  /// separates() would use for a triangle inside it: then no point of the box meets the prism
  /// (a tree's subtree, none of whose triangles can meet it, is skipped whole).
  bool separates_box(const glm::dvec3& lo, const glm::dvec3& hi) const;

 private:
  struct Side {
    glm::dvec3 normal;  // unit, out of the quad
    double level;       // normal . (its first corner)
    bool from[2];       // whether the plane may be placed at its first / second corner
  };
  std::array<glm::dvec3, 4> p_;
  glm::dvec3 normal_;
  double top_ = 0.0, bottom_ = 0.0;  // normal . x over the corners: at most top_, at least bottom_
  double size_ = 0.0, scale_ = 0.0;  // the corners' largest extent and largest coordinate
  double grow_ = 0.0;
  std::array<Side, 4> sides_;
};

}  // namespace fracref
