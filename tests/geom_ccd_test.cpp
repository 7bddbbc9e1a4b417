// Conservative CCD: single queries with exact contacts and clear misses, the iteration cap, and
// the mesh-level searches (self and against a static mesh).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "geom/ccd.hpp"
#include "geom/shapes.hpp"
#include "util/error.hpp"

namespace {

using fracref::CcdKind;
using fracref::CcdOptions;
using fracref::CcdPair;
using glm::dvec3;

TEST(GeomCcd, VertexTriangleBasics) {
  const dvec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // Through the face.
  EXPECT_TRUE(fracref::ccd_vertex_triangle({0.2, 0.2, 1}, a, b, c, {0.2, 0.2, -1}, a, b, c));
  // Ends exactly on the face; touches an edge; touches a corner.
  EXPECT_TRUE(fracref::ccd_vertex_triangle({0.2, 0.2, 1}, a, b, c, {0.2, 0.2, 0}, a, b, c));
  EXPECT_TRUE(fracref::ccd_vertex_triangle({0.5, 0.5, 1}, a, b, c, {0.5, 0.5, -1}, a, b, c));
  EXPECT_TRUE(fracref::ccd_vertex_triangle({0, 0, 1}, a, b, c, {0, 0, -1}, a, b, c));
  // Passes beside the face; stops short of it; moves parallel above it.
  EXPECT_FALSE(fracref::ccd_vertex_triangle({0.6, 0.6, 1}, a, b, c, {0.6, 0.6, -1}, a, b, c));
  EXPECT_FALSE(fracref::ccd_vertex_triangle({0.2, 0.2, 1}, a, b, c, {0.2, 0.2, 1e-3}, a, b, c));
  EXPECT_FALSE(fracref::ccd_vertex_triangle({-1, 0.2, 1e-3}, a, b, c, {2, 0.2, 1e-3}, a, b, c));
  // ... unless closer than min_distance.
  CcdOptions near;
  near.min_distance = 2e-3;
  EXPECT_TRUE(fracref::ccd_vertex_triangle({0.2, 0.2, 1}, a, b, c, {0.2, 0.2, 1e-3}, a, b, c, near));
  EXPECT_TRUE(fracref::ccd_vertex_triangle({-1, 0.2, 1e-3}, a, b, c, {2, 0.2, 1e-3}, a, b, c, near));
  // The triangle moves onto a resting point.
  EXPECT_TRUE(fracref::ccd_vertex_triangle({0.3, 0.3, 0}, a + dvec3(0, 0, 1), b + dvec3(0, 0, 1), c + dvec3(0, 0, 1),
                                           {0.3, 0.3, 0}, a - dvec3(0, 0, 1), b - dvec3(0, 0, 1), c - dvec3(0, 0, 1)));
}

TEST(GeomCcd, EdgeEdgeBasics) {
  // Edge along x at z = 1 dropping through an edge along y at z = 0.
  EXPECT_TRUE(fracref::ccd_edge_edge({-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, -1}, {1, 0, -1}, {0, -1, 0},
                                     {0, 1, 0}));
  // Dropping only to z = 1e-4; moving apart; passing beside the end of the other edge.
  EXPECT_FALSE(fracref::ccd_edge_edge({-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 1e-4}, {1, 0, 1e-4},
                                      {0, -1, 0}, {0, 1, 0}));
  EXPECT_FALSE(fracref::ccd_edge_edge({-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 2}, {1, 0, 2}, {0, -1, -1},
                                      {0, 1, -1}));
  EXPECT_FALSE(fracref::ccd_edge_edge({-1, 2, 1}, {1, 2, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 2, -1}, {1, 2, -1}, {0, -1, 0},
                                      {0, 1, 0}));
  // Parallel edges sliding onto each other (a whole segment of contact).
  EXPECT_TRUE(fracref::ccd_edge_edge({0, 0, 1}, {1, 0, 1}, {0.5, 0, 0}, {2, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0.5, 0, 0},
                                     {2, 0, 0}));
  // Touching end to end at t = 1 exactly.
  EXPECT_TRUE(fracref::ccd_edge_edge({-2, 0, 0}, {-1, 0, 0}, {1, 0, 0}, {2, 0, 0}, {-1, 0, 0}, {0, 0, 0}, {0, 0, 0},
                                     {1, 0, 0}));
}

dvec3 random_int_point(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> d(-4, 4);
  return dvec3(d(rng), d(rng), d(rng));
}

// Exact contacts built from dyadic numbers: at t = 1/2 the point sits exactly at barycentric
// weights (1/4, 1/4, 1/2) (or on an edge, or a corner) of the triangle. Every one must be found.
TEST(GeomCcd, ExactVertexTriangleContactsAreAlwaysFound) {
  std::mt19937_64 rng(21);
  const double weights[4][3] = {{0.25, 0.25, 0.5}, {0.5, 0.5, 0}, {1, 0, 0}, {0.125, 0.375, 0.5}};
  for (int it = 0; it < 4000; ++it) {
    dvec3 x0[4], x1[4];
    for (int k = 1; k < 4; ++k) {
      x0[k] = random_int_point(rng);
      x1[k] = random_int_point(rng);
    }
    const double* w = weights[it % 4];
    dvec3 mid(0.0);
    for (int k = 1; k < 4; ++k) mid += w[k - 1] * 0.5 * (x0[k] + x1[k]);
    const dvec3 v = random_int_point(rng);
    x0[0] = mid - 0.5 * v;
    x1[0] = mid + 0.5 * v;
    ASSERT_TRUE(fracref::ccd_vertex_triangle(x0[0], x0[1], x0[2], x0[3], x1[0], x1[1], x1[2], x1[3])) << it;
    const double travel[4] = {glm::length(x1[0] - x0[0]), glm::length(x1[1] - x0[1]), glm::length(x1[2] - x0[2]),
                              glm::length(x1[3] - x0[3])};
    ASSERT_TRUE(fracref::ccd_vertex_triangle(x0[0], x0[1], x0[2], x0[3], x1[0], x1[1], x1[2], x1[3], travel, {})) << it;
  }
}

TEST(GeomCcd, ExactEdgeEdgeContactsAreAlwaysFound) {
  std::mt19937_64 rng(22);
  const double params[4][2] = {{0.5, 0.5}, {0, 0.25}, {1, 1}, {0.75, 0}};
  for (int it = 0; it < 4000; ++it) {
    dvec3 x0[4], x1[4];
    for (int k = 0; k < 3; ++k) {
      x0[k] = random_int_point(rng);
      x1[k] = random_int_point(rng);
    }
    // Choose d so that at t = 1/2 the point at parameter s of edge ab equals the point at
    // parameter r of edge cd: d(1/2) = c(1/2) + (P - c(1/2)) / r, exact for the dyadics used.
    const double s = params[it % 4][0], r = std::max(params[it % 4][1], 0.5);
    const dvec3 a = 0.5 * (x0[0] + x1[0]), b = 0.5 * (x0[1] + x1[1]), c = 0.5 * (x0[2] + x1[2]);
    const dvec3 p = a + s * (b - a);
    const dvec3 dmid = c + (p - c) / r;
    const dvec3 v = random_int_point(rng);
    x0[3] = dmid - 0.5 * v;
    x1[3] = dmid + 0.5 * v;
    ASSERT_TRUE(fracref::ccd_edge_edge(x0[0], x0[1], x0[2], x0[3], x1[0], x1[1], x1[2], x1[3])) << it;
    const double travel[4] = {glm::length(x1[0] - x0[0]), glm::length(x1[1] - x0[1]), glm::length(x1[2] - x0[2]),
                              glm::length(x1[3] - x0[3])};
    ASSERT_TRUE(fracref::ccd_edge_edge(x0[0], x0[1], x0[2], x0[3], x1[0], x1[1], x1[2], x1[3], travel, {})) << it;
  }
}

// The narrow phase's cheap separation filters (projections on a few directions) must never clear
// a pair that touches: surface neighbours, nearly coplanar, that meet after a motion far shorter
// than their size (the pairs those filters are for). Dyadic coordinates make every contact exact.
TEST(GeomCcd, TinyMotionsOntoNeighboursAreAlwaysFound) {
  std::mt19937_64 rng(23);
  std::uniform_int_distribution<int> small(-8, 8), flat(-1, 1);
  auto tiny = [&] { return std::ldexp(1.0, -20) * dvec3(small(rng), small(rng), flat(rng)); };
  auto in_plane = [&] { return dvec3(small(rng), small(rng), 0.25 * flat(rng)); };
  for (int it = 0; it < 4000; ++it) {
    // Edge-edge: cd passes through the point at parameter s of ab at t = 1.
    const dvec3 a = in_plane(), b = in_plane(), u = in_plane();
    const double s = 0.125 * (it % 9);
    const dvec3 p = a + s * (b - a), c1 = p + 0.5 * u, d1 = p - 0.25 * u, w = tiny();
    const double travel[4] = {0.0, 0.0, glm::length(w), glm::length(w)};
    ASSERT_TRUE(fracref::ccd_edge_edge(a, b, c1 + w, d1 + w, a, b, c1, d1, travel, {})) << it;
    // Vertex-triangle: the vertex lands on the triangle at dyadic weights at t = 1.
    const dvec3 e = in_plane(), f = in_plane(), g = in_plane();
    const double wa = 0.125 * (it % 5), wb = 0.125 * (it % 3);
    const dvec3 q = e + wa * (f - e) + wb * (g - e);
    const double travel_vt[4] = {glm::length(w), 0.0, 0.0, 0.0};
    ASSERT_TRUE(fracref::ccd_vertex_triangle(q + w, e, f, g, q, e, f, g, travel_vt, {})) << it;
  }
}

// Only the motion of the two primitives relative to each other matters: a pair carried far by a
// common motion is settled by the filter on the travels relative to it, without the box search,
// and still found when its relative motion closes the gap.
TEST(GeomCcd, ACommonMotionIsTakenOut) {
  const dvec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), shift(5, -3, 7);
  fracref::CcdStats stats;
  EXPECT_FALSE(fracref::ccd_vertex_triangle({0.2, 0.2, 0.1}, a, b, c, dvec3(0.2, 0.2, 0.1) + shift, a + shift, b + shift,
                                            c + shift, CcdOptions{}, &stats));
  EXPECT_TRUE(stats.near);
  EXPECT_FALSE(stats.solved);
  EXPECT_TRUE(fracref::ccd_vertex_triangle({0.2, 0.2, 0.1}, a, b, c, dvec3(0.2, 0.2, -0.1) + shift, a + shift,
                                           b + shift, c + shift));
  EXPECT_FALSE(fracref::ccd_edge_edge({0, 0, 0.1}, {1, 0, 0.1}, {0.5, -1, 0}, {0.5, 1, 0}, dvec3(0, 0, 0.1) + shift,
                                      dvec3(1, 0, 0.1) + shift, dvec3(0.5, -1, 0) + shift, dvec3(0.5, 1, 0) + shift,
                                      CcdOptions{}, &stats));
  EXPECT_TRUE(stats.near);
  EXPECT_FALSE(stats.solved);
  EXPECT_TRUE(fracref::ccd_edge_edge({0, 0, 0.1}, {1, 0, 0.1}, {0.5, -1, 0}, {0.5, 1, 0}, dvec3(0, 0, -0.1) + shift,
                                     dvec3(1, 0, -0.1) + shift, dvec3(0.5, -1, 0) + shift, dvec3(0.5, 1, 0) + shift));
}

TEST(GeomCcd, IterationCapAnswersCollision) {
  const dvec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CcdOptions capped;
  capped.max_iterations = 1;
  fracref::CcdStats stats;
  // A miss that needs refinement; capped at one box it becomes a (conservative) collision.
  EXPECT_FALSE(fracref::ccd_vertex_triangle({0.6, 0.6, 1}, a, b, c, {0.6, 0.6, -1}, a, b, c, {}, &stats));
  EXPECT_FALSE(stats.hit_cap);
  EXPECT_GT(stats.boxes, 1);
  EXPECT_TRUE(fracref::ccd_vertex_triangle({0.6, 0.6, 1}, a, b, c, {0.6, 0.6, -1}, a, b, c, capped, &stats));
  EXPECT_TRUE(stats.hit_cap);
}

// Sheet of n x n cells in the plane z = height over [0,1]^2, shifted by `shift` in x and y.
fracref::TriangleSoup sheet(double height, double shift, int n) {
  return fracref::make_grid_sheet({shift, shift, height}, {1, 0, 0}, {0, 1, 0}, n, n);
}

// Two sheets in one mesh; x1 moves sheet A by da and sheet B by db.
struct TwoSheets {
  std::vector<dvec3> x0, x1;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::uint32_t split = 0;  // first vertex of sheet B
};

TwoSheets two_sheets(const dvec3& da, const dvec3& db, int n) {
  const auto a = sheet(0.0, 0.0, n), b = sheet(0.5, 0.013, n);
  TwoSheets s;
  s.x0 = a.positions;
  s.triangles = a.triangles;
  s.split = static_cast<std::uint32_t>(a.positions.size());
  s.x0.insert(s.x0.end(), b.positions.begin(), b.positions.end());
  for (auto t : b.triangles) s.triangles.push_back({t[0] + s.split, t[1] + s.split, t[2] + s.split});
  for (std::size_t v = 0; v < s.x0.size(); ++v) s.x1.push_back(s.x0[v] + (v < s.split ? da : db));
  return s;
}

TEST(GeomCcd, SheetsMovingThroughEachOtherAreCaught) {
  const auto s = two_sheets({0, 0, 0.3}, {0, 0, -0.3}, 12);
  fracref::StepCcdOptions options;
  const auto pairs = fracref::find_step_collisions(s.x0, s.x1, s.triangles, options);
  ASSERT_FALSE(pairs.empty());
  bool vertex_triangle = false, edge_edge = false;
  for (const CcdPair& p : pairs) {
    vertex_triangle |= p.kind == CcdKind::vertex_triangle;
    edge_edge |= p.kind == CcdKind::edge_edge;
    // Every pair involves both sheets.
    const bool first_in_a = p.vertices[0] < s.split;
    const bool last_in_a = p.vertices[3] < s.split;
    EXPECT_NE(first_in_a, last_in_a);
  }
  EXPECT_TRUE(vertex_triangle);
  EXPECT_TRUE(edge_edge);
  // Every interior vertex of sheet A passes through sheet B and must appear.
  std::vector<char> seen(s.x0.size(), 0);
  for (const CcdPair& p : pairs)
    if (p.kind == CcdKind::vertex_triangle) seen[p.vertices[0]] = 1;
  for (std::uint32_t v = 0; v < s.split; ++v) {
    const dvec3 x = s.x0[v];
    if (x.x > 0.02 && x.y > 0.02) {
      EXPECT_TRUE(seen[v]) << v;
    }
  }
  EXPECT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));
  options.threads = 1;
  EXPECT_EQ(fracref::find_step_collisions(s.x0, s.x1, s.triangles, options), pairs);
}

// Skipping resting pairs drops exactly the pairs whose four vertices rest, with the mesh's edges
// given in any order or derived.
TEST(GeomCcd, SkippingRestingPairsKeepsEveryPairWithMotion) {
  auto s = two_sheets({0, 0, 0.3}, {0, 0, -0.3}, 12);
  for (std::size_t v = 0; v < s.x0.size(); v += 3) s.x1[v] = s.x0[v];  // a third of the vertices rest
  const auto all = fracref::find_step_collisions(s.x0, s.x1, s.triangles);
  std::vector<CcdPair> expected;
  for (const CcdPair& p : all) {
    bool moves = false;
    for (std::uint32_t v : p.vertices) moves |= s.x0[v] != s.x1[v];
    if (moves) expected.push_back(p);
  }
  ASSERT_FALSE(expected.empty());
  fracref::StepCcdOptions options;
  options.skip_resting_pairs = true;
  EXPECT_EQ(fracref::find_step_collisions(s.x0, s.x1, s.triangles, options), expected);
  std::vector<std::array<std::uint32_t, 2>> edges;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) edges.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::reverse(edges.begin(), edges.end());
  options.edges = &edges;
  EXPECT_EQ(fracref::find_step_collisions(s.x0, s.x1, s.triangles, options), expected);
  options.skip_resting_pairs = false;
  EXPECT_EQ(fracref::find_step_collisions(s.x0, s.x1, s.triangles, options), all);
  // Nothing moves: nothing to test.
  options.skip_resting_pairs = true;
  EXPECT_TRUE(fracref::find_step_collisions(s.x0, s.x0, s.triangles, options).empty());
  // Active vertices: exactly the pairs with one of them, whether or not it moves; a few of them
  // (every 29th, 61st: under 1/16 of the vertices, and of the edges) take the scans instead of
  // the trees, with the same answer.
  std::vector<std::uint8_t> active;
  for (std::size_t stride : {7u, 29u, 61u}) {
    active.assign(s.x0.size(), 0);
    for (std::size_t v = 0; v < s.x0.size(); v += stride) active[v] = 1;
    std::vector<CcdPair> with_active;
    for (const CcdPair& p : all) {
      bool any = false;
      for (std::uint32_t v : p.vertices) any |= active[v] != 0;
      if (any) with_active.push_back(p);
    }
    ASSERT_FALSE(with_active.empty()) << stride;
    options.active_vertices = &active;
    EXPECT_EQ(fracref::find_step_collisions(s.x0, s.x1, s.triangles, options), with_active) << stride;
    options.edges = nullptr;
    EXPECT_EQ(fracref::find_step_collisions(s.x0, s.x1, s.triangles, options), with_active) << stride;
    options.edges = &edges;
  }
  std::vector<std::uint8_t> short_flags(3, 1);
  options.active_vertices = &short_flags;
  EXPECT_THROW(fracref::find_step_collisions(s.x0, s.x1, s.triangles, options), fracref::InputError);
}

// The refiner's rounds: the pairs of every colliding pair are held back (sent to x0) and the step
// is searched again for pairs with a held vertex. Testing only the first round's examined pairs
// gives exactly what a full search gives, round after round.
TEST(GeomCcd, LaterRoundsOnTheExaminedPairsMatchAFullSearch) {
  // Two sheets 0.5 apart, each vertex thrown up to ~1.5 cells (0.1) in a random direction, B's
  // towards A: tangled motion whose held-back vertices expose further pairs.
  auto s = two_sheets({0, 0, 0.2}, {0, 0, -0.2}, 15);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  for (std::size_t v = 0; v < s.x0.size(); ++v) s.x1[v] += dvec3(jitter(rng), jitter(rng), jitter(rng));
  for (std::size_t v = 0; v < s.x0.size(); v += 5) s.x1[v] = s.x0[v];
  fracref::StepCcdOptions options;
  options.skip_resting_pairs = true;
  std::vector<CcdPair> examined;
  options.examined = &examined;
  std::vector<CcdPair> pairs = fracref::find_step_collisions(s.x0, s.x1, s.triangles, options);
  options.examined = nullptr;
  ASSERT_FALSE(pairs.empty());
  EXPECT_TRUE(std::is_sorted(examined.begin(), examined.end()));
  EXPECT_TRUE(std::includes(examined.begin(), examined.end(), pairs.begin(), pairs.end()));
  EXPECT_GT(examined.size(), pairs.size());
  std::vector<std::uint8_t> held(s.x0.size(), 0);
  int rounds = 0;
  while (!pairs.empty()) {
    ASSERT_LT(++rounds, 200);
    std::fill(held.begin(), held.end(), 0);
    for (const CcdPair& p : pairs)
      for (std::uint32_t v : p.vertices)
        if (s.x1[v] != s.x0[v]) s.x1[v] = s.x0[v], held[v] = 1;
    options.active_vertices = &held;
    const auto full = fracref::find_step_collisions(s.x0, s.x1, s.triangles, options);
    options.candidates = &examined;
    EXPECT_EQ(fracref::find_step_collisions(s.x0, s.x1, s.triangles, options), full) << "round " << rounds;
    options.candidates = nullptr;
    pairs = full;
  }
  EXPECT_GE(rounds, 2);  // a round after the first found pairs
}

// The broad phase (boxes, then diagonal slabs) loses no pair: on a tangled step the search finds
// exactly what the narrow phase finds over every vertex-triangle and edge-edge pair.
TEST(GeomCcd, FindsWhatTestingEveryPairFinds) {
  auto s = two_sheets({0, 0, 0.2}, {0, 0, -0.2}, 10);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(-0.12, 0.12);
  for (std::size_t v = 0; v < s.x0.size(); ++v) s.x1[v] += dvec3(jitter(rng), jitter(rng), 3.0 * jitter(rng));
  for (std::size_t v = 0; v < s.x0.size(); v += 4) s.x1[v] = s.x0[v];
  std::vector<std::array<std::uint32_t, 2>> edges;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) edges.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<CcdPair> expected;
  const auto& x0 = s.x0;
  const auto& x1 = s.x1;
  for (std::uint32_t t = 0; t < s.triangles.size(); ++t) {
    const auto& tri = s.triangles[t];
    for (std::uint32_t v = 0; v < x0.size(); ++v)
      if (v != tri[0] && v != tri[1] && v != tri[2] &&
          fracref::ccd_vertex_triangle(x0[v], x0[tri[0]], x0[tri[1]], x0[tri[2]], x1[v], x1[tri[0]], x1[tri[1]],
                                       x1[tri[2]]))
        expected.push_back({CcdKind::vertex_triangle, {v, tri[0], tri[1], tri[2]}, t});
  }
  for (std::size_t i = 0; i < edges.size(); ++i)
    for (std::size_t j = i + 1; j < edges.size(); ++j) {
      const auto &e = edges[i], &f = edges[j];
      if (e[0] == f[0] || e[0] == f[1] || e[1] == f[0] || e[1] == f[1]) continue;
      if (fracref::ccd_edge_edge(x0[e[0]], x0[e[1]], x0[f[0]], x0[f[1]], x1[e[0]], x1[e[1]], x1[f[0]], x1[f[1]]))
        expected.push_back({CcdKind::edge_edge, {e[0], e[1], f[0], f[1]}, CcdPair::kNoTriangle});
    }
  std::sort(expected.begin(), expected.end());
  std::size_t vertex_triangle = 0;
  for (const CcdPair& p : expected) vertex_triangle += p.kind == CcdKind::vertex_triangle;
  ASSERT_GT(vertex_triangle, 50u);
  ASSERT_GT(expected.size() - vertex_triangle, 50u);
  EXPECT_EQ(fracref::find_step_collisions(s.x0, s.x1, s.triangles), expected);
}

// Against a static mesh, resting moving-mesh elements and those without an active vertex are
// left out, the rest found as without the options.
TEST(GeomCcd, StaticPairsFollowTheActiveVertices) {
  const auto box = fracref::make_box({0, 0, 0}, {1, 1, 1}, 3);
  const auto s = sheet(1.05, -0.25, 7);
  std::vector<dvec3> x1 = s.positions;
  for (std::size_t v = 0; v < x1.size(); ++v)
    if (v % 2 == 0) x1[v].z -= 0.5;  // half the vertices dive into the box
  const auto all = fracref::find_step_collisions_with_static(s.positions, x1, s.triangles, box.positions, box.triangles);
  ASSERT_FALSE(all.empty());
  std::vector<std::uint8_t> active(x1.size(), 0);
  for (std::size_t v = 0; v < x1.size(); v += 3) active[v] = 1;
  auto moving_side = [](const CcdPair& p) {
    if (p.kind == CcdKind::vertex_triangle) return std::vector<std::uint32_t>{p.vertices[0]};
    if (p.kind == CcdKind::triangle_vertex) return std::vector<std::uint32_t>{p.vertices[1], p.vertices[2], p.vertices[3]};
    return std::vector<std::uint32_t>{p.vertices[0], p.vertices[1]};
  };
  std::vector<CcdPair> moving, with_active;
  for (const CcdPair& p : all) {
    bool moves = false, any = false;
    for (std::uint32_t v : moving_side(p)) moves |= s.positions[v] != x1[v], any |= active[v] != 0;
    if (moves) moving.push_back(p);
    if (any) with_active.push_back(p);
  }
  fracref::StepCcdOptions options;
  options.skip_resting_pairs = true;
  EXPECT_EQ(fracref::find_step_collisions_with_static(s.positions, x1, s.triangles, box.positions, box.triangles, options),
            moving);
  options.active_vertices = &active;
  EXPECT_EQ(fracref::find_step_collisions_with_static(s.positions, x1, s.triangles, box.positions, box.triangles, options),
            with_active);
}

TEST(GeomCcd, SheetsMovingApartOrRigidlyAreNotCaught) {
  const auto apart = two_sheets({0, 0, -0.3}, {0, 0, 0.3}, 12);
  EXPECT_TRUE(fracref::find_step_collisions(apart.x0, apart.x1, apart.triangles).empty());
  const auto sliding = two_sheets({0.2, 0.1, 0.05}, {-0.1, 0.3, 0.2}, 12);  // both move, gap stays
  EXPECT_TRUE(fracref::find_step_collisions(sliding.x0, sliding.x1, sliding.triangles).empty());
  // A closed sphere shrinking a little: neighbours stay apart, shared-vertex pairs are skipped.
  const auto sphere = fracref::make_uv_sphere({0, 0, 0}, 1.0, 30, 40);
  std::vector<dvec3> x1 = sphere.positions;
  for (auto& p : x1) p *= 0.97;
  EXPECT_TRUE(fracref::find_step_collisions(sphere.positions, x1, sphere.triangles).empty());
}

TEST(GeomCcd, FoldingSheetIsCaught) {
  // The right half of a sheet starts folded up at 45 degrees about the line x = 0.5 and ends
  // folded under the left half: its vertices cross the left half on their straight paths.
  const auto m = sheet(0.0, 0.0, 10);
  std::vector<dvec3> x0 = m.positions, x1 = m.positions;
  for (std::size_t v = 0; v < x0.size(); ++v) {
    const dvec3 p = m.positions[v];
    if (p.x <= 0.5) continue;
    x0[v] = dvec3(p.x, p.y, p.x - 0.5);
    x1[v] = dvec3(1.03 - p.x, p.y + 0.011, -0.2 * (p.x - 0.5) - 0.01);
  }
  const auto pairs = fracref::find_step_collisions(x0, x1, m.triangles);
  ASSERT_FALSE(pairs.empty());
  // The vertex at x = 0.9 crosses z = 0 near x = 0.27, inside the left half.
  bool far_vertex = false;
  for (const CcdPair& p : pairs)
    far_vertex |= p.kind == CcdKind::vertex_triangle && std::abs(m.positions[p.vertices[0]].x - 0.9) < 1e-9;
  EXPECT_TRUE(far_vertex);
  // Without the fold-through (ending folded up at 90 degrees) nothing collides.
  for (std::size_t v = 0; v < x0.size(); ++v)
    if (m.positions[v].x > 0.5) x1[v] = dvec3(0.5, m.positions[v].y, m.positions[v].x);
  EXPECT_TRUE(fracref::find_step_collisions(x0, x1, m.triangles).empty());
}

TEST(GeomCcd, MovingAgainstStaticMesh) {
  const auto box = fracref::make_box({0, 0, 0}, {1, 1, 1}, 3);
  const auto s = sheet(1.5, -0.25, 7);  // covers the box from above, bigger than it
  std::vector<dvec3> down = s.positions, up = s.positions;
  for (auto& p : down) p.z -= 1.0;  // through the top face
  for (auto& p : up) p.z += 1.0;
  const auto pairs = fracref::find_step_collisions_with_static(s.positions, down, s.triangles, box.positions, box.triangles);
  bool kinds[3] = {false, false, false};
  for (const CcdPair& p : pairs) kinds[static_cast<int>(p.kind)] = true;
  EXPECT_TRUE(kinds[0] && kinds[1] && kinds[2]);  // vertex-triangle, triangle-vertex, edge-edge
  // The sheet ends at z = 0.5: box vertices at z = 2/3 and 1 are hit, those at 0 and 1/3 not.
  for (const CcdPair& p : pairs) {
    if (p.kind == CcdKind::triangle_vertex) {
      EXPECT_GT(box.positions[p.vertices[0]].z, 0.5);
    }
  }
  EXPECT_TRUE(fracref::find_step_collisions_with_static(s.positions, up, s.triangles, box.positions, box.triangles).empty());
  // Stopping 1e-3 above the top: clear without min_distance, a collision with it.
  std::vector<dvec3> short_of = s.positions;
  for (auto& p : short_of) p.z = 1.001;
  EXPECT_TRUE(fracref::find_step_collisions_with_static(s.positions, short_of, s.triangles, box.positions, box.triangles)
                  .empty());
  fracref::StepCcdOptions near;
  near.ccd.min_distance = 2e-3;
  EXPECT_FALSE(fracref::find_step_collisions_with_static(s.positions, short_of, s.triangles, box.positions,
                                                         box.triangles, near)
                   .empty());
}

TEST(GeomCcd, IgnoredVerticesRestingOnTheStaticMesh) {
  // A sheet whose left column rests on the top face of a box and whose other vertices move a
  // little above it: every pair with a resting vertex is a contact, the rest is clear.
  const auto box = fracref::make_box({0, 0, 0}, {1, 1, 1}, 2);
  const auto s = fracref::make_grid_sheet({0.1, 0.1, 1.0}, {0.8, 0, 0}, {0, 0.8, 0}, 4, 4);
  std::vector<dvec3> x0 = s.positions, x1 = s.positions;
  std::vector<std::uint8_t> resting(x0.size(), 0);
  for (std::size_t v = 0; v < x0.size(); ++v) {
    if (x0[v].x < 0.15) {
      resting[v] = 1;
      continue;
    }
    x0[v].z = 1.0 + 0.2 * (x0[v].x - 0.1);
    x1[v] = x0[v] + dvec3(0.01, 0.02, 0.001);
  }
  const auto touching = fracref::find_step_collisions_with_static(x0, x1, s.triangles, box.positions, box.triangles);
  ASSERT_FALSE(touching.empty());
  fracref::StepCcdOptions options;
  options.ignored_vertices = &resting;
  EXPECT_TRUE(fracref::find_step_collisions_with_static(x0, x1, s.triangles, box.positions, box.triangles, options)
                  .empty());
  resting.pop_back();
  EXPECT_THROW(fracref::find_step_collisions_with_static(x0, x1, s.triangles, box.positions, box.triangles, options),
               fracref::InputError);
}

TEST(GeomCcd, BadInputIsRejected) {
  const auto m = sheet(0.0, 0.0, 2);
  std::vector<dvec3> x1 = m.positions;
  x1.pop_back();
  EXPECT_THROW(fracref::find_step_collisions(m.positions, x1, m.triangles), fracref::InputError);
  x1 = m.positions;
  x1[3].y = NAN;
  EXPECT_THROW(fracref::find_step_collisions(m.positions, x1, m.triangles), fracref::InputError);
  auto tris = m.triangles;
  tris[1][2] = 999;
  EXPECT_THROW(fracref::find_step_collisions(m.positions, m.positions, tris), fracref::InputError);
}

}  // namespace
