// The walk of a path across B in one plane (rim::trace_in_plane): from p, the way that heads
// straightest for q, or the other way along B's section, round the other side.
#include <gtest/gtest.h>

#include <algorithm>

#include "pieces_test_support.hpp"
#include "rim/exterior_mesh.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

// Lowest and highest y of a trace's points.
std::pair<double, double> y_range(const rim::Trace& t) {
  double lo = t.from.point.y, hi = t.from.point.y;
  for (const rim::TraceStep& s : t.steps) lo = std::min(lo, s.to.point.y), hi = std::max(hi, s.to.point.y);
  return {lo, hi};
}

}  // namespace

// p and q on opposite walls of the unit box (p inside a triangle of B), at z = 0.4; that plane
// meets B in the square section. From p, up the wall x = 0 heads a little toward q (it is
// higher): the first way runs round the top (y = 1), the second round the bottom (y = 0), and
// does not turn back through p's triangle. Both end at q, every step on B.
TEST(RimTrace, TheSecondWayGoesRoundTheOtherSideOfTheSection) {
  const rim::ExteriorMesh m = rim::make_exterior_mesh(pieces_test::box(glm::dvec3(0.0), glm::dvec3(1.0), 4));
  double d = 0.0;
  const rim::Location p = rim::locate_on_exterior(m, {0.0, 0.45, 0.4}, 1e-9, &d);
  const rim::Location q = rim::locate_on_exterior(m, {1.0, 0.55, 0.4}, 1e-9, &d);
  const glm::dvec3 normal(0.0, 0.0, 1.0);
  const rim::Trace first = rim::trace_in_plane(m, p, q, 1e-12, normal, 0);
  const rim::Trace second = rim::trace_in_plane(m, p, q, 1e-12, normal, 1);
  for (const rim::Trace* t : {&first, &second}) {
    ASSERT_FALSE(t->steps.empty());
    EXPECT_TRUE(rim::same_location(t->steps.back().to, q));
    for (const rim::TraceStep& s : t->steps) {
      EXPECT_NEAR(s.to.point.z, 0.4, 1e-12);
      EXPECT_LT(closest_point(m.bvh, s.to.point).squared_distance, 1e-20);
    }
  }
  ASSERT_EQ(p.kind, rim::Location::kFace);
  EXPECT_NEAR(y_range(first).first, 0.45, 1e-12);
  EXPECT_NEAR(y_range(first).second, 1.0, 1e-12);
  EXPECT_NEAR(y_range(second).first, 0.0, 1e-12);
  EXPECT_NEAR(y_range(second).second, 0.55, 1e-12);
}

// No third way: the section passes p only twice.
TEST(RimTrace, ThereIsNoThirdWay) {
  const rim::ExteriorMesh m = rim::make_exterior_mesh(pieces_test::box(glm::dvec3(0.0), glm::dvec3(1.0), 4));
  double d = 0.0;
  const rim::Location p = rim::locate_on_exterior(m, {0.0, 0.45, 0.4}, 1e-9, &d);
  const rim::Location q = rim::locate_on_exterior(m, {1.0, 0.55, 0.4}, 1e-9, &d);
  EXPECT_THROW(rim::trace_in_plane(m, p, q, 1e-12, glm::dvec3(0.0, 0.0, 1.0), 2), RunError);
}

}  // namespace fracref

namespace fracref {

// A plane that passes a hair (2e-10, float rounding's size) above a row of B vertices, the grid
// line z = 0.5 on the wall x = 0: the walk goes through those vertices, not across each edge
// around them a hair from it (one rim point per edge at one place, which the pieces stage cannot
// order).
TEST(RimTrace, APlaneAHairFromBVerticesGoesThroughThem) {
  const rim::ExteriorMesh m = rim::make_exterior_mesh(pieces_test::box(glm::dvec3(0.0), glm::dvec3(1.0), 4));
  double d = 0.0;
  const double z = 0.5 + 2e-10;
  const rim::Location p = rim::locate_on_exterior(m, {0.0, 0.1, z}, 0.0, &d);
  const rim::Location q = rim::locate_on_exterior(m, {0.0, 0.9, z}, 0.0, &d);
  const rim::Trace t = rim::trace_in_plane(m, p, q, 1e-12, glm::dvec3(0.0, 0.0, 1.0), 0);
  ASSERT_FALSE(t.steps.empty());
  EXPECT_TRUE(rim::same_location(t.steps.back().to, q));
  int through = 0;
  glm::dvec3 last = t.from.point;
  for (const rim::TraceStep& s : t.steps) {
    EXPECT_GT(glm::distance(s.to.point, last), 1e-6) << "two trace points at one place, near " << s.to.point.y;
    last = s.to.point;
    through += s.to.kind == rim::Location::kVertex ? 1 : 0;
  }
  EXPECT_EQ(through, 3);  // (0, 0.25, 0.5), (0, 0.5, 0.5), (0, 0.75, 0.5)
}

}  // namespace fracref
