// AABB tree: box queries and overlapping pairs against brute force, closest point against
// brute force, point-in-mesh on a box and a sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <random>

#include "geom/bvh.hpp"
#include "geom/bvh_traverse.hpp"
#include "geom/shapes.hpp"
#include "util/error.hpp"

namespace {

using fracref::Aabb;
using fracref::Bvh;
using glm::dvec3;

std::vector<Aabb> random_boxes(std::mt19937_64& rng, int n, double size) {
  std::uniform_real_distribution<double> pos(0.0, 10.0), ext(0.0, size);
  std::vector<Aabb> boxes(n);
  for (auto& b : boxes) {
    b.lo = dvec3(pos(rng), pos(rng), pos(rng));
    b.hi = b.lo + dvec3(ext(rng), ext(rng), ext(rng));
  }
  return boxes;
}

fracref::TriangleSoup random_soup(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> pos(-5.0, 5.0), off(-0.7, 0.7);
  fracref::TriangleSoup m;
  for (int t = 0; t < n; ++t) {
    const dvec3 c(pos(rng), pos(rng), pos(rng));
    for (int k = 0; k < 3; ++k) m.positions.push_back(c + dvec3(off(rng), off(rng), off(rng)));
    const auto b = static_cast<std::uint32_t>(3 * t);
    m.triangles.push_back({b, b + 1, b + 2});
  }
  return m;
}

// BoxTest::float_rounded: every exactly overlapping pair, and also boxes apart by less than their
// float bounds' widening (2^-22 of the coordinates, float_bounds.hpp), but not boxes farther apart.
TEST(GeomBvh, FloatRoundedPairsAreTheExactOnesAndThoseWithinRounding) {
  std::mt19937_64 rng(9);
  std::vector<Aabb> boxes = random_boxes(rng, 400, 0.9);
  boxes.push_back({dvec3(20.0), dvec3(21.0)});
  boxes.push_back({dvec3(21.0 + 1e-12, 20.0, 20.0), dvec3(22.0, 21.0, 21.0)});  // apart by 1e-12
  boxes.push_back({dvec3(30.0), dvec3(31.0)});
  boxes.push_back({dvec3(31.0 + 1e-3, 30.0, 30.0), dvec3(32.0, 31.0, 31.0)});  // apart by ~100 floats
  const Bvh tree = fracref::build_bvh(boxes, {4});
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  auto collect = [](Pair p, std::vector<Pair>& out) { out.push_back(p); };
  auto exact = fracref::collect_overlaps<Pair>(tree, tree, true, 2, [&](std::uint32_t i, std::uint32_t j, std::vector<Pair>& out) { collect({i, j}, out); });
  auto rounded = fracref::collect_overlaps<Pair, fracref::BoxTest::float_rounded>(
      tree, tree, true, 2, [&](std::uint32_t i, std::uint32_t j, std::vector<Pair>& out) { collect({i, j}, out); });
  std::sort(exact.begin(), exact.end());
  std::sort(rounded.begin(), rounded.end());
  EXPECT_EQ(exact, fracref::self_overlapping_pairs(tree, 2));
  std::vector<Pair> extra;
  std::set_difference(rounded.begin(), rounded.end(), exact.begin(), exact.end(), std::back_inserter(extra));
  EXPECT_EQ(extra, (std::vector<Pair>{{400, 401}}));
  EXPECT_TRUE(std::includes(rounded.begin(), rounded.end(), exact.begin(), exact.end()));
}

TEST(GeomBvh, BoxQueriesAndPairsMatchBruteForce) {
  std::mt19937_64 rng(5);
  const auto a = random_boxes(rng, 700, 0.8), b = random_boxes(rng, 500, 1.2);
  const Bvh ta = fracref::build_bvh(a, {}), tb = fracref::build_bvh(b, {3});
  ASSERT_EQ(ta.items.size(), a.size());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cross, self;
  for (std::uint32_t i = 0; i < a.size(); ++i) {
    for (std::uint32_t j = 0; j < b.size(); ++j)
      if (a[i].overlaps(b[j])) cross.emplace_back(i, j);
    for (std::uint32_t j = i + 1; j < a.size(); ++j)
      if (a[i].overlaps(a[j])) self.emplace_back(i, j);
  }
  ASSERT_GT(cross.size(), 100u);
  for (int threads : {1, 2}) {
    EXPECT_EQ(fracref::overlapping_pairs(ta, tb, threads), cross);
    EXPECT_EQ(fracref::self_overlapping_pairs(ta, threads), self);
  }
  // Touching boxes overlap (closed test).
  const Bvh touching = fracref::build_bvh(std::vector<Aabb>{{dvec3(0), dvec3(1)}, {dvec3(1, 0, 0), dvec3(2, 1, 1)}});
  EXPECT_EQ(fracref::self_overlapping_pairs(touching).size(), 1u);
  std::vector<std::uint32_t> hits;
  fracref::query_box(ta, Aabb{dvec3(20), dvec3(21)}, hits);
  EXPECT_TRUE(hits.empty());
  EXPECT_FALSE(fracref::any_box(ta, Aabb{dvec3(20), dvec3(21)}));
  // any_box answers whether query_box finds anything: b's boxes as queries, some meeting a's.
  std::size_t some = 0;
  for (const Aabb& q : b) {
    hits.clear();
    fracref::query_box(ta, q, hits);
    EXPECT_EQ(fracref::any_box(ta, q), !hits.empty());
    some += !hits.empty();
  }
  EXPECT_GT(some, 10u);
  EXPECT_LT(some, b.size());
  EXPECT_TRUE(fracref::any_box(touching, Aabb{dvec3(2, 1, 1), dvec3(3)}));
  EXPECT_FALSE(fracref::any_box(fracref::build_bvh(std::vector<Aabb>{}), Aabb{dvec3(0), dvec3(1)}));
  EXPECT_TRUE(fracref::build_bvh(std::vector<Aabb>{}).nodes.empty());
}

// Subtrees a test holds for (here: boxes wholly right of a plane x = c) are skipped, and the ids
// left are query_box's less the items whose own boxes it holds for, in the same order.
TEST(GeomBvh, QueryWhereSkipsWhatTheTestHoldsFor) {
  std::mt19937_64 rng(8);
  const auto a = random_boxes(rng, 900, 0.8);
  const Bvh tree = fracref::build_bvh(a, {});
  std::size_t skipped = 0;
  for (const Aabb& q : random_boxes(rng, 50, 4.0)) {
    const double c = q.lo.x + 0.5 * (q.hi.x - q.lo.x);
    std::vector<std::uint32_t> all, where;
    fracref::query_box(tree, q, all);
    fracref::query_box_where(tree, q, [&](const Aabb& b) { return b.lo.x > c; }, where);
    std::vector<std::uint32_t> expected;
    for (std::uint32_t i : all)
      if (!(a[i].lo.x > c)) expected.push_back(i);
    EXPECT_EQ(where, expected);
    skipped += all.size() - where.size();
  }
  EXPECT_GT(skipped, 100u);
}

TEST(GeomBvh, ItemsNumberedInLeafOrderKeepTheirBoxesAndPairs) {
  std::mt19937_64 rng(12);
  const auto boxes = random_boxes(rng, 900, 0.9);
  Bvh tree = fracref::build_bvh(boxes, {8});
  const std::vector<std::uint32_t> before = tree.items;
  const auto pairs = fracref::self_overlapping_pairs(tree, 2);
  const std::vector<std::uint32_t> old = fracref::number_items_in_leaf_order(tree);
  EXPECT_EQ(old, before);
  std::vector<std::uint32_t> sorted = old;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t k = 0; k < tree.items.size(); ++k) {
    EXPECT_EQ(tree.items[k], k);
    EXPECT_EQ(sorted[k], k);  // a permutation of the old ids
    EXPECT_EQ(tree.leaf_boxes[k].lo, boxes[old[k]].lo);
  }
  // The same pairs, named by slot: mapped back, exactly the old ones.
  auto renamed = fracref::self_overlapping_pairs(tree, 2);
  for (auto& [i, j] : renamed) {
    i = old[i];
    j = old[j];
    if (j < i) std::swap(i, j);
  }
  std::sort(renamed.begin(), renamed.end());
  EXPECT_EQ(renamed, pairs);
  ASSERT_GT(pairs.size(), 100u);
}

// The single-precision leaf boxes contain the double ones at every scale, up to and beyond the
// floats' range (there the largest float, or infinity, bounds them), including zero and
// subnormal bounds.
TEST(GeomBvh, FloatLeafBoxesHoldTheirDoubleBoxes) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-45.0, 300.0);
  std::vector<Aabb> boxes;
  for (int k = 0; k < 3000; ++k) {
    const double scale = k % 7 == 0 ? 0.0 : std::pow(10.0, exponent(rng));
    Aabb b;
    b.lo = scale * dvec3(unit(rng), unit(rng), unit(rng));
    b.hi = b.lo + std::abs(unit(rng)) * scale * dvec3(1.0, 0.5, 0.25);
    boxes.push_back(b);
  }
  for (int threads : {1, 2}) {
    fracref::BvhOptions o;
    o.threads = threads;
    const Bvh bvh = fracref::build_bvh(boxes, o);
    for (std::size_t k = 0; k < bvh.leaf_boxes.size(); ++k)
      for (int a = 0; a < 3; ++a) {
        ASSERT_LE(double(bvh.float_boxes.lo[a][k]), bvh.leaf_boxes[k].lo[a]) << k << " " << a;
        ASSERT_GE(double(bvh.float_boxes.hi[a][k]), bvh.leaf_boxes[k].hi[a]) << k << " " << a;
        // Tight: within a few float steps of the double bound (or the largest float beyond it).
        const double lo = bvh.leaf_boxes[k].lo[a];
        if (std::abs(lo) < 1e38) {
          EXPECT_GE(double(bvh.float_boxes.lo[a][k]), lo - (std::abs(lo) * 1e-6 + 1e-36)) << k << " " << a;
        }
      }
  }
}

TEST(GeomBvh, ThreadedBuildGivesTheSameAnswers) {
  std::mt19937_64 rng(6);
  const auto boxes = random_boxes(rng, 30000, 0.15);
  fracref::BvhOptions two;
  two.threads = 2;
  const Bvh serial = fracref::build_bvh(boxes), threaded = fracref::build_bvh(boxes, two);
  EXPECT_EQ(serial.items, threaded.items);
  EXPECT_EQ(serial.nodes.size(), threaded.nodes.size());
  const auto pairs = fracref::self_overlapping_pairs(serial, 1);
  ASSERT_GT(pairs.size(), 1000u);
  EXPECT_EQ(fracref::self_overlapping_pairs(threaded, 2), pairs);
  std::vector<std::uint32_t> a, b;
  const Aabb probe{dvec3(4, 4, 4), dvec3(6, 5, 7)};
  fracref::query_box(serial, probe, a);
  fracref::query_box(threaded, probe, b);
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
  std::size_t brute = 0;
  for (const Aabb& box : boxes) brute += box.overlaps(probe);
  EXPECT_EQ(a.size(), brute);
}

// Boxes on a coarse lattice share their Morton codes: the two-thread radix sort must keep ties
// in id order as the one-thread sort does.
TEST(GeomBvh, ThreadedBuildKeepsTiesInIdOrder) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> cell(0, 3);
  std::vector<Aabb> boxes(40000);
  for (Aabb& box : boxes) {
    const dvec3 c(cell(rng), cell(rng), cell(rng));
    box = Aabb{c - 0.25, c + 0.25};
  }
  fracref::BvhOptions two;
  two.threads = 2;
  const Bvh serial = fracref::build_bvh(boxes), threaded = fracref::build_bvh(boxes, two);
  EXPECT_EQ(serial.items, threaded.items);
  ASSERT_EQ(serial.nodes.size(), threaded.nodes.size());
  // Items of one lattice cell (one code) come out consecutive and in ascending id order.
  for (std::size_t k = 1; k < threaded.items.size(); ++k) {
    const Aabb &a = boxes[threaded.items[k - 1]], &b = boxes[threaded.items[k]];
    if (a.lo == b.lo) {
      EXPECT_LT(threaded.items[k - 1], threaded.items[k]) << "at " << k;
    }
  }
}

TEST(GeomBvh, ClosestPointMatchesBruteForce) {
  std::mt19937_64 rng(9);
  const auto soup = random_soup(rng, 400);
  const Bvh bvh = fracref::build_bvh(soup.positions, soup.triangles);
  std::uniform_real_distribution<double> q(-7.0, 7.0);
  for (int it = 0; it < 500; ++it) {
    const dvec3 p(q(rng), q(rng), q(rng));
    const auto got = fracref::closest_point(bvh, p);
    double best = INFINITY;
    for (const auto& t : soup.triangles)
      best = std::min(best, fracref::closest_point_on_triangle(p, soup.positions[t[0]], soup.positions[t[1]],
                                                               soup.positions[t[2]])
                                .squared_distance);
    ASSERT_NEAR(got.squared_distance, best, 1e-12 * (1 + best)) << it;
    const auto& t = soup.triangles[got.triangle];
    const dvec3 rebuilt = got.barycentric[0] * soup.positions[t[0]] + got.barycentric[1] * soup.positions[t[1]] +
                          got.barycentric[2] * soup.positions[t[2]];
    EXPECT_NEAR(glm::length(rebuilt - got.point), 0.0, 1e-12);
    EXPECT_NEAR(got.barycentric[0] + got.barycentric[1] + got.barycentric[2], 1.0, 1e-12);
    EXPECT_GE(std::min({got.barycentric[0], got.barycentric[1], got.barycentric[2]}), -1e-12);
    EXPECT_NEAR(glm::dot(p - got.point, p - got.point), got.squared_distance, 1e-12 * (1 + best));
  }
}

// With a bound above the answer the bounded query gives the unbounded one's triangle and point
// bit for bit (ties included: a grid mesh's shared vertices and edges are equally near to many
// queries); with a bound at or below it, nothing.
TEST(GeomBvh, BoundedClosestPointGivesTheSameAnswer) {
  std::mt19937_64 rng(11);
  std::vector<dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (int y = 0; y <= 8; ++y)
    for (int x = 0; x <= 8; ++x) positions.emplace_back(x, y, 0.0);
  for (std::uint32_t y = 0; y < 8; ++y)
    for (std::uint32_t x = 0; x < 8; ++x) {
      const std::uint32_t v = 9 * y + x;
      triangles.push_back({v, v + 1, v + 10});
      triangles.push_back({v, v + 10, v + 9});
    }
  const auto soup = random_soup(rng, 300);
  for (const auto& mesh : {std::make_pair(positions, triangles), std::make_pair(soup.positions, soup.triangles)}) {
    const Bvh bvh = fracref::build_bvh(mesh.first, mesh.second);
    std::uniform_int_distribution<int> cell(-2, 10);
    std::uniform_real_distribution<double> q(-7.0, 7.0);
    for (int it = 0; it < 600; ++it) {
      const dvec3 p = it % 2 ? dvec3(q(rng), q(rng), q(rng)) : dvec3(cell(rng), cell(rng), 0.5 * cell(rng));
      const auto want = fracref::closest_point(bvh, p);
      for (double factor : {1.0 + 1e-12, 1.5, 100.0}) {
        const auto got = fracref::closest_point(bvh, p, want.squared_distance * factor + 1e-300);
        ASSERT_EQ(got.triangle, want.triangle) << it;
        ASSERT_EQ(got.point, want.point) << it;
        ASSERT_EQ(got.squared_distance, want.squared_distance) << it;
      }
      EXPECT_EQ(fracref::closest_point(bvh, p, want.squared_distance).squared_distance, INFINITY) << it;
    }
  }
}

TEST(GeomBvh, ClosestPointOnASphereIsRadial) {
  const auto sphere = fracref::make_uv_sphere({1, 2, 3}, 2.0, 48, 64);
  const Bvh bvh = fracref::build_bvh(sphere.positions, sphere.triangles);
  // A vertex is its own closest point.
  const auto at_vertex = fracref::closest_point(bvh, sphere.positions[100]);
  EXPECT_EQ(at_vertex.squared_distance, 0.0);
  // Far away on the +x axis: the closest point is near (3, 2, 3), within the faceting error.
  const auto far = fracref::closest_point(bvh, {10, 2, 3});
  EXPECT_NEAR(far.point.x, 3.0, 0.01);
  EXPECT_NEAR(std::sqrt(far.squared_distance), 7.0, 0.01);
}

TEST(GeomBvh, DegenerateTrianglesHaveFiniteClosestPoints) {
  const std::vector<dvec3> pos{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 5, 5}};
  const Bvh bvh = fracref::build_bvh(pos, {{0, 1, 2}, {3, 3, 3}});
  const auto c = fracref::closest_point(bvh, {1.5, 1, 0});
  EXPECT_EQ(c.triangle, 0u);
  EXPECT_NEAR(c.squared_distance, 1.0, 1e-15);
  EXPECT_NEAR(c.point.x, 1.5, 1e-15);
}

TEST(GeomBvh, PointInBox) {
  const auto box = fracref::make_box({-1, -2, -3}, {1, 2, 3}, 4);
  const Bvh bvh = fracref::build_bvh(box.positions, box.triangles);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> q(-4.0, 4.0);
  int inside = 0;
  for (int it = 0; it < 3000; ++it) {
    dvec3 p(q(rng), q(rng), q(rng));
    if (it % 3 == 0) p = glm::round(p * 2.0) / 2.0;  // on the grid lines and planes of the faces
    const bool expected = std::abs(p.x) <= 1 && std::abs(p.y) <= 2 && std::abs(p.z) <= 3;
    ASSERT_EQ(fracref::point_in_mesh(bvh, p), expected) << p.x << " " << p.y << " " << p.z;
    inside += expected;
  }
  EXPECT_GT(inside, 200);
  // On the surface: face, edge, corner count as inside; one ulp out does not.
  EXPECT_TRUE(fracref::point_in_mesh(bvh, {1, 0.3, 0.1}));
  EXPECT_TRUE(fracref::point_in_mesh(bvh, {1, 2, 0.7}));
  EXPECT_TRUE(fracref::point_in_mesh(bvh, {-1, -2, -3}));
  EXPECT_FALSE(fracref::point_in_mesh(bvh, {std::nextafter(1.0, 2.0), 0.3, 0.1}));
  EXPECT_TRUE(fracref::point_in_mesh(bvh, {std::nextafter(1.0, 0.0), 0.3, 0.1}));
}

TEST(GeomBvh, PointInSphereAgreesWithWindingNumber) {
  const auto sphere = fracref::make_uv_sphere({0.5, -0.25, 0.125}, 1.0, 24, 32);
  const Bvh bvh = fracref::build_bvh(sphere.positions, sphere.triangles);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> q(-1.5, 1.5);
  int inside = 0;
  for (int it = 0; it < 1000; ++it) {
    const dvec3 p = dvec3(0.5, -0.25, 0.125) + dvec3(q(rng), q(rng), q(rng));
    const double w = fracref::winding_number(bvh, p);
    const bool in = fracref::point_in_mesh(bvh, p);
    ASSERT_NEAR(w, in ? 1.0 : 0.0, 1e-6) << it;
    const double r = glm::length(p - dvec3(0.5, -0.25, 0.125));
    if (r < 0.98) {
      EXPECT_TRUE(in);
    }
    if (r > 1.0) {
      EXPECT_FALSE(in);
    }
    inside += in;
  }
  EXPECT_GT(inside, 100);
}

TEST(GeomBvh, BadMeshesAreRejected) {
  const std::vector<dvec3> pos{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_THROW(fracref::build_bvh(pos, {{0, 1, 3}}), fracref::InputError);
  EXPECT_THROW(fracref::build_bvh({{0, 0, 0}, {NAN, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}), fracref::InputError);
}

}  // namespace
