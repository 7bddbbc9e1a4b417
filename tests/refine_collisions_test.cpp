// The collision constraints applied again on one step (refine/collisions.hpp, StepCollisions).
#include <gtest/gtest.h>

#include <random>

#include "refine/collisions.hpp"
#include "refine/exterior.hpp"
#include "refine_test_support.hpp"

namespace fracref {
namespace {

using test::unit_cube;

// A later call of StepCollisions, after other checks held vertices back, holds exactly what a new
// search from scratch holds.
TEST(StepCollisions, LaterCallsMatchANewSearch) {
  static const ExteriorSurface b = make_exterior(unit_cube(), "cube");
  const FractureSurface s = test::sheet_of(12, [](int i, int j) { return 0.5f + 0.02f * float((i * 7 + j * 3) % 5); });
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.3f, 0.3f);
  std::vector<glm::vec4> x1 = s.positions;
  for (std::size_t i = 0; i < x1.size(); ++i)
    if (!(s.vertex_flags[i] & kVertexBoundary)) x1[i] += glm::vec4(0.3f * u(rng), 0.3f * u(rng), u(rng), 0.0f);
  StepCollisions collisions(s, b, s.positions);
  const std::size_t first = collisions.apply(x1);
  ASSERT_GT(first, 0u) << "the motion should collide somewhere";
  for (int round = 0; round < 3; ++round) {
    std::size_t others = 0;  // hold every fifth vertex still moving, as the other checks would
    for (std::size_t i = 0; i < x1.size(); ++i)
      if (x1[i] != s.positions[i] && (i + round) % 5 == 0) x1[i] = s.positions[i], ++others;
    ASSERT_GT(others, 0u);
    std::vector<glm::vec4> fresh = x1;
    const std::size_t fresh_held = apply_collision_constraints(s, b, s.positions, fresh);
    EXPECT_EQ(collisions.apply(x1), fresh_held);
    EXPECT_EQ(x1, fresh);
  }
}

}  // namespace
}  // namespace fracref
