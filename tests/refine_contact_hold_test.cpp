// The flow step and the contact rule with B where the rule is cautious: at a concave edge of B.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "flow/backend.hpp"
#include "refine/exterior.hpp"
#include "refine/refine.hpp"
#include "pieces_test_support.hpp"
#include "refine_test_support.hpp"

namespace fracref {
namespace {

// An n x n grid sheet in the L prism below, from its concave edge (1, 1, z) to (1 + slant, 0, z)
// on its wall y = 0, z in [0, 1].
FractureSurface sheet_from_crease(int n, float slant) {
  std::vector<glm::vec4> p;
  std::vector<glm::uvec4> f;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float t = float(i) / float(n);
      p.push_back({1.0f + slant * t, 1.0f - t, float(j) / float(n), 1.0f});
    }
  auto id = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), 0});
      f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1), 0});
    }
  return make_fracture_surface(p, f, std::vector<glm::ivec2>(f.size(), glm::ivec2(1, 0)), 2);
}

// ψ's valley: the plane x = 0.9, 0.2 wide on either side, left of the sheet.
double valley_left_of_the_sheet(const glm::dvec3& p) { return 0.3 + 3.0 * std::min(std::abs(p.x - 0.9), 0.2); }

}  // namespace

// A sheet from the notch's concave edge (x = y = 1) to the wall y = 0, leaning 0.1 past the notch's
// wall plane x = 1: the corners of its faces on the crease lie inside B but outside that plane, so
// the contact rule (refine/exterior_contact.hpp), cautious there, flags those faces at the start.
// ψ pulls the sheet left, past x = 1, and the step is long. In the second iteration the full
// step frees those faces but raises E, and every shorter length leaves them flagged with their
// corners moved (and folds faces by the crease): held only where the full step left them
// flagged, they made the line search refuse every length, and the iteration did not move S (the
// bunny's demo stalled so at its 14th). Held from the start of the step, they stay, and the rest
// moves.
TEST(RefineContactHold, FacesFlaggedAtTheStartOfAStepDoNotStallIt) {
  const ExteriorSurface b = make_exterior(pieces_test::voxel_surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 1.0), "L prism");
  const FieldGrid4 field = test::field_on_box({0, 0, 0}, {2, 2, 1}, 40, 3, valley_left_of_the_sheet);
  FractureSurface s = sheet_from_crease(8, 0.1f);
  for (std::uint32_t v = 0; v < s.positions.size(); ++v) {
    if (s.positions[v].y < 1.0f && s.positions[v].y > 0.8f) {
      ASSERT_GT(s.positions[v].x, 1.0f);
    }
  }
  auto backend = make_cpu_backend(2);
  RefineOptions o;
  o.scale = b.diagonal();
  o.max_iterations = 3;
  o.step = 0.1;
  const RefineResult r = refine_surface(s, field, b, *backend, o);
  ASSERT_EQ(r.iterations.size(), 3u);
  for (std::size_t i = 0; i < r.iterations.size(); ++i) EXPECT_GT(r.iterations[i].max_displacement, 0.0) << "iteration " << i;
  EXPECT_LT(r.iterations.back().energy, r.initial_energy);
  EXPECT_EQ(validate(s), "");
}

}  // namespace fracref
