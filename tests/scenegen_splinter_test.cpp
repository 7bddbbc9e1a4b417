// The tree branch's splintered coarse crack (splinter_cut): splinters where the branch snaps
// open, none at the hinge, and every face of the cut pulled apart or slid, never closed, by the
// opening turn.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>

#include "scenegen/scenegen_internal.hpp"
#include "util/error.hpp"

namespace {
using namespace fracref;
using namespace fracref::scenegen_detail;

constexpr int kLayers = 24;
constexpr double kFront = -0.3;

TetSet branch_tets() { return cylinder_tets(1.0, 4.0, {1, 8, 14, 16}, kLayers); }

Strength uniform(double zeta) {
  return [zeta](const glm::dvec3&) { return zeta; };
}

/// The smallest separation rate over the cut's faces: the motion of side 0 turned by -a about
/// the hinge line less that of side 1 turned by +a (per unit sin a), along the face normal from
/// side 1 towards side 0. Negative means two faces run into each other.
double least_opening(const TetSet& set, const SplinterCut& cut) {
  const TetFaces faces = tet_faces(set);
  double least = HUGE_VAL;
  for (std::size_t f = 0; f < faces.interior.size(); ++f) {
    const glm::uvec2 t = faces.interior_tets[f];
    if (cut.side[t.x] == cut.side[t.y]) continue;
    const glm::uvec3 tri = faces.interior[f];
    const glm::dvec3 a = set.positions[tri.x], b = set.positions[tri.y], c = set.positions[tri.z];
    const glm::dvec3 p = (a + b + c) / 3.0;
    if (p.y <= kFront) continue;  // not cracked: the hinge
    const std::uint32_t lower = cut.side[t.x] == 0 ? t.x : t.y, upper = lower == t.x ? t.y : t.x;
    glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
    if (glm::dot(n, tet_centroid(set, lower) - tet_centroid(set, upper)) < 0.0) n = -n;
    const glm::dvec3 relative(0.0, 2.0 * p.z, -2.0 * (p.y - kFront));
    least = std::min(least, glm::dot(relative, n));
  }
  return least;
}

/// "" when each side's tets bound a 2-manifold solid, else what is wrong.
std::string sides_manifold(const TetSet& set, const SplinterCut& cut) {
  for (const int side : {0, 1}) {
    TetSet part;
    part.positions = set.positions;
    for (std::size_t t = 0; t < set.tets.size(); ++t)
      if (cut.side[t] == side) part.tets.push_back(set.tets[t]);
    const auto defects = surface_defects(tet_faces(part).hull);
    if (!defects.empty())
      return "side " + std::to_string(side) + ": " + std::to_string(defects.size()) + " defects, the first at " +
             std::to_string(defects.front().first) + "-" + std::to_string(defects.front().second);
  }
  return "";
}

int most_layers(const SplinterCut& cut) {
  int most = 0;
  for (const int h : cut.height) most = std::max(most, std::abs(h));
  return most;
}

}  // namespace

TEST(ScenegenSplinter, EveryFaceOpensUnderTheTurn) {
  const TetSet set = branch_tets();
  for (const bool flip : {false, true}) {
    SplinterOptions options;
    options.front = kFront, options.flip = flip;
    const SplinterCut cut = splinter_cut(set, kLayers, uniform(0.8), options);
    EXPECT_GE(least_opening(set, cut), -1e-12) << "flip " << flip;
    EXPECT_EQ(sides_manifold(set, cut), "") << "flip " << flip;
    EXPECT_GE(most_layers(cut), 5);  // 10 × tension × 0.8 at the far side
    int up = 0, down = 0;
    for (const int h : cut.height) up += h > 0, down += h < 0;
    EXPECT_GT(up, 2);
    EXPECT_GT(down, 2);
  }
}

TEST(ScenegenSplinter, TheTurnWouldCloseTheWantedSplinters) {
  // The check above can fail: with every column breaking where it wants, regardless of its
  // neighbours (an opening rule of -1 lets any wall through), some faces close.
  const TetSet set = branch_tets();
  SplinterOptions options;
  options.front = kFront, options.min_wall_slope = -1.0;
  const SplinterCut cut = splinter_cut(set, kLayers, uniform(0.8), options);
  EXPECT_LT(least_opening(set, cut), -0.1);
}

TEST(ScenegenSplinter, NoSplintersAtTheHingeOrInVeryWeakWood) {
  const TetSet set = branch_tets();
  SplinterOptions options;
  options.front = kFront;
  const SplinterCut cut = splinter_cut(set, kLayers, uniform(0.8), options);
  const std::size_t columns = cut.height.size();
  ASSERT_EQ(columns, 60u);
  std::size_t at_hinge = 0;
  for (std::size_t i = 0; i < columns; ++i) {
    double lowest = HUGE_VAL;  // over column i's prism in layer 0, tets 3i .. 3i + 2
    for (std::uint32_t t = std::uint32_t(3 * i); t < 3 * i + 3; ++t)
      for (int k = 0; k < 4; ++k) lowest = std::min(lowest, set.positions[set.tets[t][k]].y);
    if (lowest <= kFront + 0.05) {  // the column reaches down to the hinge: the cut opens too little there
      EXPECT_EQ(cut.height[i], 0) << "column " << i;
      ++at_hinge;
    }
  }
  EXPECT_GT(at_hinge, 20u);
  // Wood of ζ = 0.02 snaps where it is bent: 10 × 0.02 rounds to no layer.
  EXPECT_EQ(most_layers(splinter_cut(set, kLayers, uniform(0.02), options)), 0);
}

TEST(ScenegenSplinter, StrongFibresPullOutFarther) {
  const TetSet set = branch_tets();
  SplinterOptions options;
  options.front = kFront;
  const Strength strong_right = [](const glm::dvec3& p) { return p.x > 0.0 ? 0.9 : 0.3; };
  const SplinterCut cut = splinter_cut(set, kLayers, strong_right, options);
  int right = 0, left = 0;
  for (std::size_t i = 0; i < cut.height.size(); ++i) {
    int& side = tet_centroid(set, std::uint32_t(3 * i)).x > 0.0 ? right : left;
    side = std::max(side, std::abs(cut.height[i]));
  }
  EXPECT_GT(right, left);
  EXPECT_GE(least_opening(set, cut), -1e-12);
  EXPECT_EQ(sides_manifold(set, cut), "");
}

TEST(ScenegenSplinter, TheBranchMaterialSplintersTheCut) {
  const TetSet set = branch_tets();
  SplinterOptions options;
  options.front = kFront;
  const SplinterCut cut =
      splinter_cut(set, kLayers, material_strength("branch", 1, {-1.0, -1.0, -2.0}, {1.0, 1.0, 2.0}), options);
  EXPECT_GE(least_opening(set, cut), -1e-12);
  EXPECT_EQ(sides_manifold(set, cut), "");
  EXPECT_GE(most_layers(cut), 3);
  std::size_t steps = 0;
  for (const int h : cut.height) steps += h != 0;
  EXPECT_GE(steps, 10u);
  EXPECT_GT(cut.faces.size(), 60u);  // the disc's part beyond the front, and the walls
}

TEST(ScenegenSplinter, RejectsOtherMeshes) {
  EXPECT_THROW(splinter_cut(cylinder_tets(1.0, 4.0, {1, 8}, 5), 5, uniform(0.5), {}), RunError);
  EXPECT_THROW(splinter_cut(box_lattice({glm::dvec3(0.0), glm::dvec3(1.0), {2, 2, 2}}), 2, uniform(0.5), {}), RunError);
}
