#pragma once
// Exact orientation predicates on double inputs (Shewchuk 1997): a floating-point filter with a
// proven error bound, and an exact expansion-arithmetic evaluation when the filter cannot decide.
#include <glm/glm.hpp>

namespace fracref {

/// Sign of the 2D orientation determinant
///   | ax-cx  ay-cy |
///   | bx-cx  by-cy |
/// evaluated exactly: +1 when a, b, c are in counterclockwise order, -1 clockwise, 0 collinear.
/// \pre finite inputs; coordinate differences either zero or above ~1e-150 in magnitude and
///      below ~1e150 (no underflow or overflow of the products; true for any mesh coordinates).
int orient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c);

/// orient2d on the projection of 3D points that drops coordinate `drop_axis` (0, 1 or 2),
/// keeping the other two in increasing axis order: exact, since dropping a coordinate is exact.
int orient2d_projected(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, int drop_axis);

/// Sign of the 3D orientation determinant det[a-d; b-d; c-d], evaluated exactly:
/// +1 when d lies below the plane through a, b, c (the side opposite to the normal
/// (b-a)x(c-a), i.e. a, b, c appear counterclockwise seen from above), -1 above, 0 coplanar.
/// \pre as orient2d.
int orient3d(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

/// How often the exact fallback ran since program start, summed over all threads (diagnostics
/// and tests only; relaxed atomic counters).
struct PredicateStats {
  unsigned long long orient2d_exact = 0;
  unsigned long long orient3d_exact = 0;
};
PredicateStats predicate_stats();

}  // namespace fracref
