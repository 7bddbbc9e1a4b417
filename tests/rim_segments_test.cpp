// Rim segments inside a triangle of B (rim/exterior_mesh.hpp): which triangle a segment between
// two locations runs inside (segment_face), and whether two such segments cross there
// (segments_cross_in_face), the test both the refiner's set-up and its flow make before the
// pieces stage cuts B along the rim.
#include <gtest/gtest.h>

#include "pieces_test_support.hpp"
#include "rim/exterior_mesh.hpp"

namespace fracref {
namespace {

// The location with barycentric weights (1 − u − v, u, v) in triangle f: (u, v) is its place in
// f's barycentric plane (location_uv).
rim::Location at(const rim::ExteriorMesh& m, std::uint32_t f, double u, double v) {
  return rim::location_from_weights(m, f, glm::dvec3(1.0 - u - v, u, v));
}

}  // namespace

// In one triangle: a segment from (0.2, 0.2) to (0.2, 0.6) and one from (0.6, 0.2) to (0.1, 0.5)
// cross at (0.2, 0.44). Sharing an end, ending on the other segment, or running beside it, they
// do not; nor in either order of their ends.
TEST(RimSegments, TwoSegmentsCrossOnlyAtAPointInsideBoth) {
  const rim::ExteriorMesh m = rim::make_exterior_mesh(pieces_test::box(glm::dvec3(0.0), glm::dvec3(1.0), 2));
  const std::uint32_t f = 0;
  const rim::Location a = at(m, f, 0.2, 0.2), b = at(m, f, 0.2, 0.6);
  ASSERT_EQ(rim::segment_face(m, a, b), f);
  EXPECT_TRUE(rim::segments_cross_in_face(m, f, a, b, at(m, f, 0.6, 0.2), at(m, f, 0.1, 0.5)));
  EXPECT_TRUE(rim::segments_cross_in_face(m, f, b, a, at(m, f, 0.1, 0.5), at(m, f, 0.6, 0.2)));
  EXPECT_FALSE(rim::segments_cross_in_face(m, f, a, b, a, at(m, f, 0.6, 0.2))) << "a shared end";
  EXPECT_FALSE(rim::segments_cross_in_face(m, f, a, b, at(m, f, 0.2, 0.4), at(m, f, 0.5, 0.4))) << "ends on ab";
  EXPECT_FALSE(rim::segments_cross_in_face(m, f, a, b, at(m, f, 0.5, 0.2), at(m, f, 0.5, 0.45))) << "beside ab";
  EXPECT_FALSE(rim::segments_cross_in_face(m, f, a, b, at(m, f, 0.1, 0.1), at(m, f, 0.15, 0.7))) << "beside ab";
}

// A segment runs inside the triangle that holds both its ends, unless both lie on one side of it
// (the pieces stage orders those among the points on their B edge); ends with no triangle in
// common give none.
TEST(RimSegments, ASegmentRunsInsideTheTriangleOfBothEndsUnlessAlongItsSide) {
  const rim::ExteriorMesh m = rim::make_exterior_mesh(pieces_test::box(glm::dvec3(0.0), glm::dvec3(1.0), 2));
  const std::uint32_t f = 0, e = m.face_edges[f][0];
  const rim::Location on_side_a = rim::edge_location(m, e, 0.25), on_side_b = rim::edge_location(m, e, 0.75);
  EXPECT_EQ(rim::segment_face(m, on_side_a, on_side_b), rim::kNone) << "along side 0";
  EXPECT_EQ(rim::segment_face(m, on_side_a, at(m, f, 0.3, 0.3)), f);
  std::uint32_t far = 1;
  while (rim::common_face(m, at(m, far, 0.3, 0.3), at(m, f, 0.3, 0.3)) != rim::kNone) ++far;
  EXPECT_EQ(rim::segment_face(m, at(m, f, 0.3, 0.3), at(m, far, 0.3, 0.3)), rim::kNone);
}

}  // namespace fracref
