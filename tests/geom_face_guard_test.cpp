// FaceGuard: new faces are tested against the snapshot's faces and against every face accepted
// since, whether it sits in an indexed run or in the unindexed tail.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "geom/face_guard.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

// A row of n small triangles in the plane z = 0, triangle k over x in [k, k + 0.8].
struct Row {
  std::vector<glm::dvec3> positions;
  std::vector<TriangleIds> faces;
};

Row row(int n, double z) {
  Row r;
  for (int k = 0; k < n; ++k) {
    const auto base = std::uint32_t(r.positions.size());
    r.positions.push_back({k, 0.0, z});
    r.positions.push_back({k + 0.8, 0.0, z});
    r.positions.push_back({k + 0.4, 0.8, z});
    r.faces.push_back({base, base + 1, base + 2});
  }
  return r;
}

// A vertical triangle that pierces the plane z = h inside the triangle over [k, k + 0.8].
std::vector<TriangleIds> piercing(FaceGuard& g, int k, double h) {
  const std::uint32_t a = g.add_vertex({k + 0.4, 0.3, h - 0.5});
  const std::uint32_t b = g.add_vertex({k + 0.4, 0.5, h - 0.5});
  const std::uint32_t c = g.add_vertex({k + 0.4, 0.4, h + 0.5});
  return {{a, b, c}};
}

TEST(FaceGuard, SnapshotFacesBlockUnlessReplaced) {
  Row r = row(4, 0.0);
  FaceGuard g(r.positions, r.faces);
  const auto t = piercing(g, 2, 0.0);
  EXPECT_FALSE(g.clear(t, {}));
  EXPECT_TRUE(g.clear(t, {2}));
  g.accept({}, {2});
  EXPECT_TRUE(g.clear(t, {}));
}

// A hit found ahead on the snapshot decides as clear() does: no hit, a hit not gone, a hit gone
// since (the face it met replaced by an accepted edit) while another snapshot face still blocks,
// and one gone with nothing else in the way; replaced faces are never hits.
TEST(FaceGuard, FirstSnapshotHitDecidesAsClear) {
  Row r = row(6, 0.0);
  // A second sheet face right over triangle 3, so a piercing face there meets two snapshot faces.
  const auto top = std::uint32_t(r.positions.size());
  r.positions.push_back({3.0, 0.0, 0.2});
  r.positions.push_back({3.8, 0.0, 0.2});
  r.positions.push_back({3.4, 0.8, 0.2});
  r.faces.push_back({top, top + 1, top + 2});
  FaceGuard g(r.positions, r.faces);
  const auto at1 = piercing(g, 1, 0.0), at3 = piercing(g, 3, 0.0), clear_of_all = piercing(g, 1, 3.0);
  EXPECT_EQ(g.first_snapshot_hit(clear_of_all, {}), FaceGuard::kNoHit);
  EXPECT_TRUE(g.clear_given(clear_of_all, {}, FaceGuard::kNoHit));
  EXPECT_EQ(g.first_snapshot_hit(at1, {}), 1u);
  EXPECT_EQ(g.first_snapshot_hit(at1, {1}), FaceGuard::kNoHit);
  const std::uint32_t hit3 = g.first_snapshot_hit(at3, {});
  ASSERT_TRUE(hit3 == 3u || hit3 == 6u);
  const std::uint32_t hit1 = g.first_snapshot_hit(at1, {});
  EXPECT_FALSE(g.clear_given(at1, {}, hit1));
  g.accept({}, {hit3});  // the face the hit found is gone; the other one over it is not
  EXPECT_EQ(g.clear_given(at3, {}, hit3), g.clear(at3, {}));
  EXPECT_FALSE(g.clear_given(at3, {}, hit3));
  g.accept({}, {1});
  EXPECT_TRUE(g.clear_given(at1, {}, hit1));
  EXPECT_EQ(g.clear_given(at1, {}, hit1), g.clear(at1, {}));
}

// 1000 accepted faces (a row at z = 5, added one by one): the runs merge several times; a face
// piercing any of them is refused, one piercing none is accepted.
TEST(FaceGuard, AcceptedFacesBlockInEveryRunAndInTheTail) {
  Row base = row(1, -3.0);
  FaceGuard g(base.positions, base.faces);
  const int n = 1000;
  const Row upper = row(n, 5.0);
  std::vector<std::uint32_t> ids;
  for (const glm::dvec3& p : upper.positions) ids.push_back(g.add_vertex(p));
  for (const TriangleIds& f : upper.faces) g.accept({{ids[f[0]], ids[f[1]], ids[f[2]]}}, {});
  for (int k : {0, 1, 31, 32, 500, 511, 512, 767, 960, 990, 999}) {
    SCOPED_TRACE("accepted face " + std::to_string(k));
    EXPECT_FALSE(g.clear(piercing(g, k, 5.0), {}));
  }
  EXPECT_TRUE(g.clear(piercing(g, n + 3, 5.0), {}));  // beyond the row
  EXPECT_TRUE(g.clear(piercing(g, 10, 2.0), {}));     // under it
}

// A guard over regions indexes only the faces near them and answers as the full guard does for
// new faces inside a region; new faces outside every region are a caller's error.
TEST(FaceGuard, RegionsAnswerAsTheFullGuardInsideThem) {
  const Row r = row(40, 0.0);
  Aabb near_5, near_30;  // around the triangles over [5, 5.8] and [30, 30.8], through z = 0
  near_5.expand(glm::dvec3(4.9, -0.1, -1.0)), near_5.expand(glm::dvec3(6.0, 1.0, 2.0));
  near_30.expand(glm::dvec3(29.9, -0.1, -1.0)), near_30.expand(glm::dvec3(31.0, 1.0, 2.0));
  FaceGuard full(r.positions, r.faces), regional(r.positions, r.faces, {near_5, near_30});
  for (int k : {5, 30}) {
    SCOPED_TRACE("triangle " + std::to_string(k));
    const auto a = piercing(full, k, 0.0), b = piercing(regional, k, 0.0);
    EXPECT_FALSE(full.clear(a, {}));
    EXPECT_FALSE(regional.clear(b, {}));
    EXPECT_TRUE(regional.clear(b, {std::uint32_t(k)}));
    EXPECT_TRUE(regional.clear(piercing(regional, k, 0.8), {}));  // above the row, still inside the region
  }
  EXPECT_THROW(regional.clear(piercing(regional, 12, 0.0), {}), RunError);  // outside both regions
  // An accepted face inside a region blocks as it does in the full guard.
  const auto upper = piercing(regional, 30, 0.0);
  regional.accept(upper, {30});
  EXPECT_TRUE(regional.clear(piercing(regional, 5, 0.0), {5}));
  const std::uint32_t a = regional.add_vertex({30.2, 0.4, 0.0}), b = regional.add_vertex({30.6, 0.4, 0.0}),
                      c = regional.add_vertex({30.4, 0.6, 0.0});
  EXPECT_FALSE(regional.clear({{a, b, c}}, {}));  // across the accepted vertical face
}

// Two jittered grid sheets, z = 0 and z = h; returns the positions and faces, cell (i, j) of sheet
// l as faces 2 (l n² + i n + j) and the next, split by the diagonal from corner (i, j).
Row sheets(int n, double h, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  Row r;
  for (int l = 0; l < 2; ++l)
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) r.positions.push_back({i + jitter(rng), j + jitter(rng), l * h + jitter(rng)});
  auto id = [&](int l, int i, int j) { return std::uint32_t(l * (n + 1) * (n + 1) + i * (n + 1) + j); };
  for (int l = 0; l < 2; ++l)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        r.faces.push_back({id(l, i, j), id(l, i + 1, j), id(l, i + 1, j + 1)});
        r.faces.push_back({id(l, i, j), id(l, i + 1, j + 1), id(l, i, j + 1)});
      }
  return r;
}

// With `reach` (how far the split's new vertex is off the edge) the guard passes over the faces
// beyond it and answers exactly as without; told a reach that is too short, it passes over faces
// the new ones do meet (so the faces beyond it are really left out).
TEST(FaceGuard, ReachPassesOverFarFacesWithTheSameAnswers) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), height(0.05, 0.4);
  const int n = 8;
  int blocked = 0, free = 0, fooled = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Row r = sheets(n, height(rng), rng);
    FaceGuard g(r.positions, r.faces);
    for (int k = 0; k < 20; ++k) {
      const int l = int(rng() % 2), i = int(rng() % n), j = int(rng() % n);
      const std::uint32_t f0 = std::uint32_t(2 * (l * n * n + i * n + j)), f1 = f0 + 1;
      const std::uint32_t a = r.faces[f0][0], b = r.faces[f0][2];  // the shared diagonal
      const glm::dvec3 mid = 0.5 * (r.positions[a] + r.positions[b]);
      const glm::dvec3 m = mid + 0.6 * glm::dvec3(unit(rng), unit(rng), unit(rng));
      const std::uint32_t v = g.add_vertex(m);
      const std::vector<TriangleIds> faces = {
          {a, v, r.faces[f0][1]}, {v, b, r.faces[f0][1]}, {a, v, r.faces[f1][2]}, {v, b, r.faces[f1][2]}};
      const double reach = glm::distance(m, mid);
      const std::uint32_t hit = g.first_snapshot_hit(faces, {f0, f1});
      EXPECT_EQ(g.first_snapshot_hit(faces, {f0, f1}, reach), hit);
      const bool clear = g.clear(faces, {f0, f1});
      EXPECT_EQ(g.clear(faces, {f0, f1}, reach), clear);
      EXPECT_EQ(g.clear_given(faces, {f0, f1}, hit, reach), clear);
      clear ? ++free : ++blocked;
      if (!clear && g.clear(faces, {f0, f1}, 0.1 * reach)) ++fooled;
    }
  }
  EXPECT_GT(blocked, 50);
  EXPECT_GT(free, 50);
  EXPECT_GT(fooled, 10) << blocked << " " << free << " " << fooled;
}

}  // namespace
}  // namespace fracref
