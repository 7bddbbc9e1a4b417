// Exact triangle intersection: hand-made cases, a randomized cross-check against an exact
// separating-axis test in 128-bit integers, and the mesh-level self-intersection search.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "geom/intersect.hpp"
#include "geom/shapes.hpp"
#include "util/error.hpp"

namespace {

using fracref::find_self_intersections;
using fracref::mesh_faces_intersect;
using fracref::Triangle3;
using fracref::TriangleIds;
using fracref::triangles_intersect;
using glm::dvec3;

// ---- An independent exact reference: separating axes for convex planar polygons. ----
using I = __int128;
struct V {
  I x, y, z;
};
V operator-(const V& a, const V& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V cross(const V& a, const V& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
I dot(const V& a, const V& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
bool is_zero(const V& a) { return a.x == 0 && a.y == 0 && a.z == 0; }

V normal_of(const std::vector<V>& p) {
  for (std::size_t i = 2; i < p.size(); ++i) {
    const V n = cross(p[1] - p[0], p[i] - p[0]);
    if (!is_zero(n)) return n;
  }
  return {0, 0, 0};
}

// Closed convex planar polygons (non-degenerate) intersect iff no candidate axis separates
// them: both normals, edge x edge, and the in-plane edge normals.
bool sat_intersect(const std::vector<V>& p, const std::vector<V>& q) {
  const V np = normal_of(p), nq = normal_of(q);
  std::vector<V> axes{np, nq};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const V e = p[(i + 1) % p.size()] - p[i];
    axes.push_back(cross(np, e));
    for (std::size_t j = 0; j < q.size(); ++j) axes.push_back(cross(e, q[(j + 1) % q.size()] - q[j]));
  }
  for (std::size_t j = 0; j < q.size(); ++j) axes.push_back(cross(nq, q[(j + 1) % q.size()] - q[j]));
  for (const V& axis : axes) {
    if (is_zero(axis)) continue;
    I pmin = dot(axis, p[0]), pmax = pmin, qmin = dot(axis, q[0]), qmax = qmin;
    for (const V& v : p) pmin = std::min(pmin, dot(axis, v)), pmax = std::max(pmax, dot(axis, v));
    for (const V& v : q) qmin = std::min(qmin, dot(axis, v)), qmax = std::max(qmax, dot(axis, v));
    if (pmax < qmin || qmax < pmin) return false;
  }
  return true;
}

V to_v(const dvec3& p, I scale = 1) { return {I(p.x) * scale, I(p.y) * scale, I(p.z) * scale}; }
V lerp_toward(const dvec3& from, const dvec3& to, I scale) {  // from*scale + (to - from): a 1/scale step
  return {I(from.x) * scale + I(to.x - from.x), I(from.y) * scale + I(to.y - from.y), I(from.z) * scale + I(to.z - from.z)};
}

bool degenerate(const dvec3& a, const dvec3& b, const dvec3& c) { return is_zero(cross(to_v(b) - to_v(a), to_v(c) - to_v(a))); }

dvec3 random_point(std::mt19937_64& rng, int range) {
  std::uniform_int_distribution<int> d(-range, range);
  return dvec3(d(rng), d(rng), d(rng));
}

// ---- Hand-made cases ----

TEST(GeomIntersect, BasicCases) {
  const Triangle3 t{dvec3(0, 0, 0), dvec3(2, 0, 0), dvec3(0, 2, 0)};
  // Crossing: a vertical triangle piercing t's interior.
  EXPECT_TRUE(triangles_intersect(t, {dvec3(0.5, 0.5, -1), dvec3(0.5, 0.5, 1), dvec3(3, 3, 0.5)}));
  // Touching at a vertex: one vertex on t's interior, the rest above.
  EXPECT_TRUE(triangles_intersect(t, {dvec3(0.5, 0.5, 0), dvec3(0, 0, 1), dvec3(1, 0, 1)}));
  // The same, lifted by one ulp: disjoint.
  EXPECT_FALSE(triangles_intersect(t, {dvec3(0.5, 0.5, 0x1p-60), dvec3(0, 0, 1), dvec3(1, 0, 1)}));
  // Disjoint, far.
  EXPECT_FALSE(triangles_intersect(t, {dvec3(5, 5, 5), dvec3(6, 5, 5), dvec3(5, 6, 5)}));
  // Coplanar overlap, coplanar containment, coplanar edge contact, coplanar disjoint.
  EXPECT_TRUE(triangles_intersect(t, {dvec3(1, 1, 0), dvec3(-1, 1, 0), dvec3(1, -1, 0)}));
  EXPECT_TRUE(triangles_intersect(t, {dvec3(0.1, 0.1, 0), dvec3(0.5, 0.1, 0), dvec3(0.1, 0.5, 0)}));
  EXPECT_TRUE(triangles_intersect(t, {dvec3(1, 1, 0), dvec3(2, 2, 0), dvec3(0, 2, 0)}));
  EXPECT_FALSE(triangles_intersect(t, {dvec3(1.5, 1.5, 0), dvec3(3, 3, 0), dvec3(1, 3, 0)}));
  // Edge against edge, crossing at one point in space.
  EXPECT_TRUE(triangles_intersect(t, {dvec3(1, -1, 0), dvec3(1, 1, 0), dvec3(1, 0, 5)}));
  // Degenerate triangles: a needle through t, a needle beside it, a point on t.
  EXPECT_TRUE(triangles_intersect(t, {dvec3(0.5, 0.5, -1), dvec3(0.5, 0.5, 1), dvec3(0.5, 0.5, 0)}));
  EXPECT_FALSE(triangles_intersect(t, {dvec3(3, 3, -1), dvec3(3, 3, 1), dvec3(3, 3, 0)}));
  EXPECT_TRUE(triangles_intersect(t, {dvec3(1, 0.5, 0), dvec3(1, 0.5, 0), dvec3(1, 0.5, 0)}));
  EXPECT_FALSE(triangles_intersect(t, {dvec3(1, 1.5, 0), dvec3(1, 1.5, 0), dvec3(1, 1.5, 0)}));
}

// All orders of the corners of both faces give the same answer.
void expect_faces(const std::vector<dvec3>& pos, TriangleIds a, TriangleIds b, bool expected) {
  for (int flip = 0; flip < 2; ++flip)
    for (int ra = 0; ra < 3; ++ra)
      for (int rb = 0; rb < 3; ++rb) {
        TriangleIds x{a[ra], a[(ra + 1) % 3], a[(ra + 2) % 3]}, y{b[rb], b[(rb + 1) % 3], b[(rb + 2) % 3]};
        if (flip) std::swap(x[1], x[2]);
        EXPECT_EQ(mesh_faces_intersect(pos, x, y), expected);
        EXPECT_EQ(mesh_faces_intersect(pos, y, x), expected);
      }
}

TEST(GeomIntersect, SharedVertexAndSharedEdgeCases) {
  const std::vector<dvec3> pos{
      {0, 0, 0},      // 0: shared
      {2, 0, 0},      // 1
      {0, 2, 0},      // 2
      {-2, 0, 0},     // 3: fan neighbour, coplanar, outside the wedge of (0,1,2)
      {0, -2, 0},     // 4
      {1, 1, 1},      // 5: above
      {1, 1, -1},     // 6: below -> (0,5,6) crosses (0,1,2) along a segment from 0
      {1, 0.5, 0},    // 7: inside wedge of (0,1,2), coplanar
      {1, -1, 0},     // 8
      {0.5, 0.5, 0},  // 9: inside (0,1,2)
      {-1, -1, 1},    // 10
  };
  expect_faces(pos, {0, 1, 2}, {0, 3, 4}, false);   // coplanar fan, touching only at 0
  expect_faces(pos, {0, 1, 2}, {0, 5, 10}, false);  // out of the plane, only at 0
  expect_faces(pos, {0, 1, 2}, {0, 5, 6}, true);    // shared vertex but crossing
  expect_faces(pos, {0, 1, 2}, {0, 7, 8}, true);    // coplanar, overlapping wedges
  expect_faces(pos, {0, 1, 2}, {0, 9, 5}, true);    // an edge from 0 runs inside the face
  expect_faces(pos, {0, 1, 2}, {0, 1, 8}, false);   // shared edge, flat, opposite sides
  expect_faces(pos, {0, 1, 2}, {0, 1, 5}, false);   // shared edge, dihedral
  expect_faces(pos, {0, 1, 2}, {0, 1, 9}, true);    // shared edge, folded over (coplanar, same side)
  expect_faces(pos, {0, 1, 2}, {0, 1, 2}, true);    // duplicated face
  expect_faces(pos, {0, 1, 2}, {3, 4, 10}, false);  // no shared id, apart
  expect_faces(pos, {0, 1, 2}, {9, 5, 10}, true);   // no shared id, touching at 9
}

TEST(GeomIntersect, DegenerateFacesSharingVertices) {
  const std::vector<dvec3> pos{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, 2}, {3, 0, 0}};
  expect_faces(pos, {0, 1, 2}, {0, 3, 1}, false);  // shares edge 0-1; a needle lying on that edge
  expect_faces(pos, {0, 1, 2}, {0, 4, 5}, false);  // ordinary face sharing 0, away
  expect_faces(pos, {0, 1, 2}, {0, 3, 7}, true);   // needle from 0 along edge 0-1
  expect_faces(pos, {0, 1, 2}, {0, 4, 7}, true);   // needle through 0 covering edge 0-1 partly
  expect_faces(pos, {0, 5, 6}, {0, 3, 4}, false);  // two needles meeting at 0 only
  expect_faces(pos, {0, 5, 6}, {0, 6, 3}, false);  // needle and face sharing edge 0-6
}

TEST(GeomIntersect, RandomPairsMatchSeparatingAxes) {
  std::mt19937_64 rng(1);
  int hits = 0, tested = 0;
  for (int it = 0; it < 150000; ++it) {
    const Triangle3 p{random_point(rng, 2), random_point(rng, 2), random_point(rng, 2)};
    const Triangle3 q{random_point(rng, 2), random_point(rng, 2), random_point(rng, 2)};
    if (degenerate(p[0], p[1], p[2]) || degenerate(q[0], q[1], q[2])) continue;
    const bool expected = sat_intersect({to_v(p[0]), to_v(p[1]), to_v(p[2])}, {to_v(q[0]), to_v(q[1]), to_v(q[2])});
    ASSERT_EQ(triangles_intersect(p, q), expected) << it;
    ASSERT_EQ(triangles_intersect(q, p), expected) << it;
    const std::vector<dvec3> pos{p[0], p[1], p[2], q[0], q[1], q[2]};
    ASSERT_EQ(mesh_faces_intersect(pos, {0, 1, 2}, {3, 4, 5}), expected) << it;
    ASSERT_EQ(mesh_faces_intersect(pos, {4, 5, 3}, {0, 1, 2}), expected) << it;
    hits += expected;
    ++tested;
  }
  EXPECT_GT(hits, tested / 10);
  EXPECT_LT(hits, tested * 9 / 10);
}

// Faces of a bumpy sheet and its neighbours, the pairs that mesh_faces_intersect decides in
// projection: nearly coplanar, close, sharing one vertex or none.
TEST(GeomIntersect, NearlyCoplanarNeighboursMatchSeparatingAxes) {
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> xy(-6, 6), z(-1, 1);
  const I scale = I(1) << 20;
  int hits = 0, tested = 0;
  for (int it = 0; it < 60000; ++it) {
    std::vector<dvec3> pos(6);
    for (dvec3& p : pos) p = dvec3(xy(rng), xy(rng), z(rng));
    const bool shared = it % 2 == 1;
    if (shared) pos[3] = pos[0];
    if (degenerate(pos[0], pos[1], pos[2]) || degenerate(pos[3], pos[4], pos[5])) continue;
    bool expected;
    if (shared) {
      const std::vector<V> cut{to_v(pos[1], scale), to_v(pos[2], scale), lerp_toward(pos[0], pos[2], scale),
                               lerp_toward(pos[0], pos[1], scale)};
      expected = sat_intersect(cut, {to_v(pos[0], scale), to_v(pos[4], scale), to_v(pos[5], scale)});
      ASSERT_EQ(mesh_faces_intersect(pos, {0, 1, 2}, {0, 4, 5}), expected) << it;
      ASSERT_EQ(mesh_faces_intersect(pos, {5, 0, 4}, {1, 2, 0}), expected) << it;
    } else {
      expected = sat_intersect({to_v(pos[0]), to_v(pos[1]), to_v(pos[2])}, {to_v(pos[3]), to_v(pos[4]), to_v(pos[5])});
      ASSERT_EQ(mesh_faces_intersect(pos, {0, 1, 2}, {3, 4, 5}), expected) << it;
      ASSERT_EQ(mesh_faces_intersect(pos, {4, 5, 3}, {2, 0, 1}), expected) << it;
    }
    hits += expected;
    ++tested;
  }
  EXPECT_GT(hits, tested / 20);
  EXPECT_LT(hits, tested * 19 / 20);
}

// Meeting beyond the shared vertex s of (s,a,b) and (s,c,d) is meeting of (s,c,d) with (s,a,b)
// cut short near s; with integer corners a 2^-20 cut is far below any feature of the input.
TEST(GeomIntersect, RandomSharedVertexPairsMatchSeparatingAxes) {
  std::mt19937_64 rng(2);
  const I scale = I(1) << 20;
  int hits = 0, tested = 0;
  for (int it = 0; it < 60000; ++it) {
    const std::vector<dvec3> pos{random_point(rng, 2), random_point(rng, 2), random_point(rng, 2),
                                 random_point(rng, 2), random_point(rng, 2)};
    if (degenerate(pos[0], pos[1], pos[2]) || degenerate(pos[0], pos[3], pos[4])) continue;
    const std::vector<V> cut{to_v(pos[1], scale), to_v(pos[2], scale), lerp_toward(pos[0], pos[2], scale),
                             lerp_toward(pos[0], pos[1], scale)};
    const bool expected = sat_intersect(cut, {to_v(pos[0], scale), to_v(pos[3], scale), to_v(pos[4], scale)});
    ASSERT_EQ(mesh_faces_intersect(pos, {0, 1, 2}, {0, 3, 4}), expected) << it;
    ASSERT_EQ(mesh_faces_intersect(pos, {0, 3, 4}, {2, 0, 1}), expected) << it;
    hits += expected;
    ++tested;
  }
  EXPECT_GT(hits, tested / 20);
}

TEST(GeomIntersect, RandomSharedEdgePairsMatchSeparatingAxes) {
  std::mt19937_64 rng(4);
  const I scale = I(1) << 20;
  int hits = 0, tested = 0;
  for (int it = 0; it < 60000; ++it) {
    std::vector<dvec3> pos{random_point(rng, 1), random_point(rng, 1), random_point(rng, 1), random_point(rng, 1)};
    if (it % 2) pos[3].z = pos[2].z = pos[1].z = pos[0].z;  // force many coplanar folds
    if (degenerate(pos[0], pos[1], pos[2]) || degenerate(pos[0], pos[1], pos[3])) continue;
    // (0,1,2) cut away from the shared edge 0-1: the corners at weight 2^-20 toward 2.
    const std::vector<V> cut{to_v(pos[2], scale), lerp_toward(pos[0], pos[2], scale), lerp_toward(pos[1], pos[2], scale)};
    const bool expected = sat_intersect(cut, {to_v(pos[0], scale), to_v(pos[1], scale), to_v(pos[3], scale)});
    ASSERT_EQ(mesh_faces_intersect(pos, {0, 1, 2}, {1, 0, 3}), expected) << it;
    hits += expected;
    ++tested;
  }
  EXPECT_GT(hits, 100);
}

// ---- Mesh level ----

TEST(GeomIntersect, ClosedMeshesHaveNoSelfIntersections) {
  const auto box = fracref::make_box({0, 0, 0}, {1, 2, 3}, 6);  // many coplanar neighbours
  EXPECT_TRUE(find_self_intersections(box.positions, box.triangles, 100).empty());
  const auto sphere = fracref::make_uv_sphere({0.1, 0.2, 0.3}, 1.5, 40, 60);
  EXPECT_TRUE(find_self_intersections(sphere.positions, sphere.triangles, 100).empty());
}

TEST(GeomIntersect, PushedVertexMatchesBruteForceForAnyThreadCount) {
  auto sphere = fracref::make_uv_sphere({0, 0, 0}, 1.0, 12, 16);
  sphere.positions[40] = -1.3 * sphere.positions[40];  // through the opposite side
  std::vector<std::pair<std::uint32_t, std::uint32_t>> brute;
  for (std::uint32_t i = 0; i < sphere.triangles.size(); ++i)
    for (std::uint32_t j = i + 1; j < sphere.triangles.size(); ++j)
      if (mesh_faces_intersect(sphere.positions, sphere.triangles[i], sphere.triangles[j])) brute.emplace_back(i, j);
  ASSERT_FALSE(brute.empty());
  for (int threads : {1, 2, 3}) {
    fracref::SelfIntersectionOptions options;
    options.threads = threads;
    EXPECT_EQ(find_self_intersections(sphere.positions, sphere.triangles, options), brute);
    options.max_report = 3;
    const auto first = find_self_intersections(sphere.positions, sphere.triangles, options);
    const std::vector<std::pair<std::uint32_t, std::uint32_t>> head(brute.begin(), brute.begin() + 3);
    EXPECT_EQ(first, head);
  }
}

// query_faces: only pairs whose first face is below it (the faces after it are tested against
// the ones before only, never against each other).
TEST(GeomIntersect, QueryFacesLimitsThePairsToThoseWithAnEarlyFace) {
  auto sphere = fracref::make_uv_sphere({0, 0, 0}, 1.0, 12, 16);
  sphere.positions[40] = -1.3 * sphere.positions[40];
  const auto all = find_self_intersections(sphere.positions, sphere.triangles, 1000);
  ASSERT_GT(all.size(), 2u);
  const std::uint32_t cut = all[all.size() / 2].first + 1;  // some pairs start below, some above
  std::vector<std::pair<std::uint32_t, std::uint32_t>> expected;
  for (const auto& p : all)
    if (p.first < cut) expected.push_back(p);
  ASSERT_LT(expected.size(), all.size());
  fracref::SelfIntersectionOptions options;
  options.query_faces = cut;
  EXPECT_EQ(find_self_intersections(sphere.positions, sphere.triangles, options), expected);
}

TEST(GeomIntersect, BadFacesAreRejectedWithTheirIndex) {
  const std::vector<dvec3> pos{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  try {
    find_self_intersections(pos, {{0, 1, 2}, {0, 1, 7}}, 10);
    FAIL() << "no exception";
  } catch (const fracref::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("triangle 1"), std::string::npos) << e.what();
  }
  try {
    find_self_intersections(pos, {{0, 2, 2}}, 10);
    FAIL() << "no exception";
  } catch (const fracref::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("face 0"), std::string::npos) << e.what();
  }
}

}  // namespace
