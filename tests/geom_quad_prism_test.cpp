// QuadPrism: a triangle it separates from a quad's tetrahedron meets none of the tetrahedron's
// faces (exact, as mesh faces: shared corners by id) and is not inside it; and it separates most
// triangles that are clear of it, at a corner or not.
#include <gtest/gtest.h>

#include <random>

#include "geom/intersect.hpp"
#include "geom/quad_prism.hpp"

namespace fracref {
namespace {

using glm::dvec3;

struct Case {
  std::vector<dvec3> x;  // the quad's corners (ids 0..3, in order around it), then g's
  std::array<int, 3> shared{-1, -1, -1};
};

// A quad around the origin in the plane z = 0 folded along its diagonal 0-2 by up to `fold`
// radians, and a random triangle near it; with `corner` >= 0 the triangle's first corner is that
// quad corner.
Case random_case(std::mt19937_64& rng, double fold, int corner) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0), angle(-fold, fold);
  Case c;
  const double r[4] = {1.0 + 0.4 * unit(rng), 1.0 + 0.4 * unit(rng), 1.0 + 0.4 * unit(rng), 1.0 + 0.4 * unit(rng)};
  for (int k = 0; k < 4; ++k) {
    const double t = (k + 0.3 * unit(rng)) * M_PI / 2.0;
    c.x.push_back({r[k] * std::cos(t), r[k] * std::sin(t), 0.0});
  }
  // Fold corners 1 and 3 out of the plane about the diagonal 0-2 (rotation about the z-free axis).
  for (int k : {1, 3}) c.x[std::size_t(k)].z = std::tan(angle(rng)) * 0.5 * glm::length(c.x[std::size_t(k)]);
  const dvec3 centre(1.2 * unit(rng), 1.2 * unit(rng), 0.4 * unit(rng));
  for (int k = 0; k < 3; ++k) c.x.push_back(centre + 0.6 * dvec3(unit(rng), unit(rng), unit(rng)));
  if (corner >= 0) {
    c.x[4] = c.x[std::size_t(corner)];
    c.shared[0] = corner;
  }
  return c;
}

bool meets_tetrahedron(const Case& c) {
  const TriangleIds g = {c.shared[0] >= 0 ? std::uint32_t(c.shared[0]) : 4u, 5u, 6u};
  const TriangleIds faces[4] = {{0, 1, 2}, {0, 2, 3}, {0, 1, 3}, {1, 2, 3}};
  for (const TriangleIds& f : faces)
    if (mesh_faces_intersect(c.x, f, g)) return true;
  return false;
}

TEST(QuadPrism, SeparatedTrianglesMeetNoFaceOfTheTetrahedron) {
  std::mt19937_64 rng(21);
  int separated[2] = {0, 0}, clear[2] = {0, 0};
  for (int it = 0; it < 40000; ++it) {
    const int corner = it % 2 ? int(rng() % 4) : -1;
    const Case c = random_case(rng, 25.0 * M_PI / 180.0, corner);
    const QuadPrism prism({c.x[0], c.x[1], c.x[2], c.x[3]}, glm::cross(c.x[2] - c.x[0], c.x[3] - c.x[1]));
    const bool sep = prism.separates({c.x[4], c.x[5], c.x[6]}, c.shared);
    const bool meets = meets_tetrahedron(c);
    ASSERT_FALSE(sep && meets) << "case " << it;
    const int kind = corner >= 0 ? 1 : 0;
    if (!meets) ++clear[kind];
    if (sep) ++separated[kind];
  }
  // Most triangles clear of the tetrahedron are found so (those inside it or across two sides
  // near a corner are not).
  EXPECT_GT(separated[0], clear[0] / 2) << separated[0] << " of " << clear[0];
  EXPECT_GT(separated[1], clear[1] / 4) << separated[1] << " of " << clear[1];
}

// A triangle lying in the quad's plane just outside one side, and one touching that side: the
// first is separated, the second not; two shared corners are never separated.
TEST(QuadPrism, TouchingAndSharedEdgesAreNotSeparated) {
  const std::array<dvec3, 4> q = {dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(1, 1, 0), dvec3(0, 1, 0)};
  const QuadPrism prism(q, dvec3(0, 0, 1));
  EXPECT_TRUE(prism.separates({dvec3(1.01, 0.2, 0), dvec3(2, 0.5, 0), dvec3(1.5, 0.9, 0)}, {-1, -1, -1}));
  EXPECT_FALSE(prism.separates({dvec3(1.0, 0.2, 0), dvec3(2, 0.5, 0), dvec3(1.5, 0.9, 0)}, {-1, -1, -1}));
  EXPECT_TRUE(prism.separates({q[1], dvec3(2, 0.5, 0), dvec3(1.5, 0.9, 0)}, {1, -1, -1}));
  EXPECT_FALSE(prism.separates({q[1], q[2], dvec3(2, 0.5, 0)}, {1, 2, -1}));
  EXPECT_TRUE(prism.separates({dvec3(0.2, 0.2, 0.5), dvec3(0.8, 0.2, 0.5), dvec3(0.5, 0.8, 0.5)}, {-1, -1, -1}));
  EXPECT_FALSE(prism.separates({dvec3(0.2, 0.2, 0.0), dvec3(0.8, 0.2, 0.5), dvec3(0.5, 0.8, 0.5)}, {-1, -1, -1}));
  // A dart (corner 3 inside the triangle of the others): the planes through its sides at corner 3
  // would cut the tetrahedron, so they are left out, and a triangle inside it is not separated.
  const QuadPrism dart({dvec3(0, 0, 0), dvec3(2, 1, 0), dvec3(0, 2, 0), dvec3(0.5, 1, 0)}, dvec3(0, 0, 1));
  EXPECT_FALSE(dart.separates({dvec3(0.05, 0.9, 0), dvec3(0.15, 0.95, 0), dvec3(0.1, 1.1, 0)}, {-1, -1, -1}));
  EXPECT_TRUE(dart.separates({dvec3(2.1, 1, 0), dvec3(3, 1, 0), dvec3(3, 2, 0)}, {-1, -1, -1}));
}

// A box the prism separates holds no triangle it does not separate (random triangles inside such
// boxes, touching their faces and corners), and boxes clear of it are mostly found so.
TEST(QuadPrism, SeparatedBoxesHoldOnlySeparatedTriangles) {
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), frac(0.0, 1.0);
  int boxes_separated = 0, boxes_clear = 0;
  for (int it = 0; it < 20000; ++it) {
    const Case c = random_case(rng, 25.0 * M_PI / 180.0, -1);
    const double grow = it % 3 == 0 ? 0.0 : 0.2 * frac(rng);
    const QuadPrism prism({c.x[0], c.x[1], c.x[2], c.x[3]}, glm::cross(c.x[2] - c.x[0], c.x[3] - c.x[1]), grow);
    const dvec3 centre(2.0 * unit(rng), 2.0 * unit(rng), 1.0 * unit(rng));
    const dvec3 half(0.5 * frac(rng), 0.5 * frac(rng), 0.5 * frac(rng));
    const dvec3 lo = centre - half, hi = centre + half;
    const bool sep = prism.separates_box(lo, hi);
    boxes_separated += sep;
    // Corners of the box, and points on its faces, as triangles' corners.
    auto corner = [&](unsigned m) { return dvec3(m & 1 ? hi.x : lo.x, m & 2 ? hi.y : lo.y, m & 4 ? hi.z : lo.z); };
    auto inside = [&] { return lo + dvec3(frac(rng), frac(rng), frac(rng)) * (hi - lo); };
    bool all = true;
    for (int t = 0; t < 8; ++t) {
      const std::array<dvec3, 3> g = t < 4 ? std::array<dvec3, 3>{corner(rng() % 8), corner(rng() % 8), corner(rng() % 8)}
                                           : std::array<dvec3, 3>{inside(), inside(), corner(rng() % 8)};
      all = all && prism.separates(g, {-1, -1, -1});
    }
    if (sep) {
      ASSERT_TRUE(all) << "case " << it;
    }
    boxes_clear += all;
  }
  EXPECT_GT(boxes_separated, boxes_clear / 2) << boxes_separated << " of " << boxes_clear;
}

}  // namespace
}  // namespace fracref
