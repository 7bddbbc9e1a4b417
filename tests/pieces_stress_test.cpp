// build_pieces on many seeded random cuts: planar and wavy sheets at random orientations and
// offsets through spheres of several resolutions, coarser and finer than the sheet.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

#include "pieces_test_support.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using namespace pieces_test;

struct Case {
  MeshSoup exterior;
  std::string name;
};

TEST(PiecesStress, RandomDisksThroughSpheres) {
  MeshSoup bumpy = icosphere(3);
  for (glm::dvec3& p : bumpy.positions) p *= 1.0 + 0.04 * std::sin(7.0 * p.x) * std::cos(5.0 * p.y + 3.0 * p.z);
  const std::vector<Case> cases = {{icosphere(1), "icosphere 1"},
                                   {icosphere(3), "icosphere 3"},
                                   {to_soup(make_uv_sphere({0, 0, 0}, 1.0, 12, 16)), "uv sphere"},
                                   {box({-1, -0.8, -0.9}, {1, 0.8, 0.9}, 1), "box 1"},
                                   {box({-1, -0.8, -0.9}, {1, 0.8, 0.9}, 5), "box 5"},
                                   {bumpy, "bumpy sphere"}};
  const char* env = std::getenv("PIECES_STRESS_TRIALS");
  const int trials = env ? std::atoi(env) : 12;
  std::mt19937_64 rng(7);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * double(rng() >> 11) * 0x1.0p-53; };
  int built = 0;
  for (const Case& c : cases)
    for (int trial = 0; trial < trials; ++trial) {
      const glm::dvec3 n(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      const glm::dvec3 centre(uniform(-0.4, 0.4), uniform(-0.4, 0.4), uniform(-0.4, 0.4));
      const int rings = 2 + trial % 3, segments = 8 + 7 * (trial % 5);
      const Bvh bvh = build_bvh(c.exterior.positions, c.exterior.triangles);
      const FractureSurface s =
          combine_sheets({disk_sheet(bvh, centre, n, trial % 2 ? 0.05 : 0.0, rings, segments, uniform(0, 3))}, 2);
      SCOPED_TRACE(c.name + ", trial " + std::to_string(trial));
      PieceSet set;
      try {
        set = build_pieces(s, c.exterior);
      } catch (const RunError& e) {
        ADD_FAILURE() << e.what();
        continue;
      }
      expect_valid_pieces(set, c.exterior);
      ++built;
    }
  EXPECT_EQ(built, int(cases.size()) * trials);
}

// Many S boundary vertices inside each B triangle (S much finer than B), and long traces across
// many small B triangles (S much coarser than B).
TEST(PiecesStress, ResolutionExtremes) {
  struct Extreme {
    int levels, rings, segments;
  };
  for (const Extreme& e : {Extreme{1, 6, 240}, Extreme{5, 2, 9}, Extreme{4, 3, 40}}) {
    const MeshSoup b = icosphere(e.levels);
    const Bvh bvh = build_bvh(b.positions, b.triangles);
    const FractureSurface s =
        combine_sheets({disk_sheet(bvh, {0.1, -0.2, 0.05}, {0.3, 0.2, 1.0}, 0.04, e.rings, e.segments, 0.7)}, 2);
    SCOPED_TRACE("icosphere " + std::to_string(e.levels) + ", " + std::to_string(e.segments) + " segments");
    const PieceSet set = build_pieces(s, b);
    expect_valid_pieces(set, b);
  }
}

}  // namespace
}  // namespace fracref
