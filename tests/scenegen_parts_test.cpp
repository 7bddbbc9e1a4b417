// The building blocks of the demo scenes: exteriors, structured and stuffed tet meshes, piece
// layouts and duplicated vertices.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "geom/bvh.hpp"
#include "scenegen/scenegen_internal.hpp"

namespace {
using namespace fracref;
using namespace fracref::scenegen_detail;

/// "" when every directed edge is used once and its reverse once.
std::string closed(const std::vector<glm::uvec3>& faces) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const glm::uvec3& f : faces)
    for (int e = 0; e < 3; ++e) ++directed[{f[e], f[(e + 1) % 3]}];
  for (const auto& [e, n] : directed)
    if (n != 1 || directed.count({e.second, e.first}) == 0 || directed.at({e.second, e.first}) != 1)
      return "edge " + std::to_string(e.first) + "-" + std::to_string(e.second);
  return "";
}

std::vector<glm::uvec3> faces_of(const TriMesh& m) {
  std::vector<glm::uvec3> out;
  for (const auto& t : m.triangles) out.push_back({t[0], t[1], t[2]});
  return out;
}

double total_volume(const TetSet& set) {
  double v = 0.0;
  for (std::uint32_t t = 0; t < set.tets.size(); ++t) v += tet_volume(set, t);
  return v;
}

double min_volume(const TetSet& set) {
  double v = 1e300;
  for (std::uint32_t t = 0; t < set.tets.size(); ++t) v = std::min(v, tet_volume(set, t));
  return v;
}

TEST(ScenegenParts, ExteriorsAreClosedAndOutward) {
  const TriMesh cylinder = make_cylinder(1.0, 8.0, 32, 32);
  EXPECT_EQ(cylinder.positions.size(), 33u * 32u + 2u);
  EXPECT_EQ(cylinder.triangles.size(), 2u * 32u * 32u + 64u);
  EXPECT_EQ(closed(faces_of(cylinder)), "");
  EXPECT_NEAR(mesh_volume(cylinder), 8.0 * 16.0 * std::sin(2.0 * std::numbers::pi / 32.0), 1e-12);
  const TriMesh box = make_box({-1.5, 0.0, -0.1}, {1.5, 1.0, 0.1}, {6, 2, 1});
  EXPECT_EQ(box.triangles.size(), 2u * 2u * (12u + 6u + 2u));
  EXPECT_EQ(closed(faces_of(box)), "");
  EXPECT_NEAR(mesh_volume(box), 0.6, 1e-12);
  const TriMesh rounded = make_box({-0.5, -1.0, -1.0}, {0.5, 1.0, 1.0}, {20, 40, 40}, 0.25);
  EXPECT_EQ(closed(faces_of(rounded)), "");
  // A box of 1 x 2 x 2 less what rounding its edges and corners takes (r = 0.25).
  const double r = 0.25, edges = (4 - std::numbers::pi) * r * r * (4 * 0.5 + 4 * 1.5 + 4 * 1.5) / 4.0;
  const double corners = 8.0 * (r * r * r - std::numbers::pi * r * r * r / 6.0);
  EXPECT_NEAR(mesh_volume(rounded), 4.0 - edges - corners, 0.01);
}

TEST(ScenegenParts, RoundedBoxMapKeepsFlatPartsAndRoundsEdges) {
  const glm::dvec3 lo(-0.5, -1.0, -1.0), hi(0.5, 1.0, 1.0);
  EXPECT_EQ(rounded_box_map({0.5, 0.1, 0.2}, lo, hi, 0.25), glm::dvec3(0.5, 0.1, 0.2));
  EXPECT_EQ(rounded_box_map({0.0, 0.3, -0.2}, lo, hi, 0.25), glm::dvec3(0.0, 0.3, -0.2));
  const glm::dvec3 corner = rounded_box_map(hi, lo, hi, 0.25);
  EXPECT_NEAR(glm::distance(corner, hi - 0.25), 0.25, 1e-15);
}

TEST(ScenegenParts, BoxLatticeFillsTheBox) {
  const TetSet set = box_lattice({{0.0, 0.0, 0.0}, {3.0, 1.0, 0.2}, {15, 5, 2}});
  EXPECT_EQ(set.tets.size(), 15u * 5u * 2u * 6u);
  EXPECT_EQ(set.positions.size(), 16u * 6u * 3u);
  EXPECT_GT(min_volume(set), 0.0);
  EXPECT_NEAR(total_volume(set), 0.6, 1e-12);
  const TetFaces faces = tet_faces(set);
  EXPECT_EQ(faces.hull.size(), 2u * 2u * (15u * 5u + 15u * 2u + 5u * 2u));
  EXPECT_EQ(closed(faces.hull), "");
}

TEST(ScenegenParts, CylinderTetsConformAndTouchTheExterior) {
  const TetSet set = cylinder_tets(1.0, 8.0, {1, 8, 14, 16}, 24);
  EXPECT_EQ(set.positions.size(), 25u * 39u);
  EXPECT_EQ(set.tets.size(), 24u * 60u * 3u);
  EXPECT_GT(min_volume(set), 0.0);
  const TetFaces faces = tet_faces(set);
  EXPECT_EQ(closed(faces.hull), "");
  EXPECT_TRUE(surface_defects(faces.hull).empty());
  // The hull is the 16-gon prism; its outer vertices are the exterior's even ring vertices.
  EXPECT_NEAR(total_volume(set), 8.0 * 8.0 * std::sin(2.0 * std::numbers::pi / 16.0), 1e-9);
  const TriMesh exterior = make_cylinder(1.0, 8.0, 32, 32);
  for (int k = 0; k < 16; ++k) {
    const glm::dvec3 p = set.positions[12 * 39 + 23 + k], q = exterior.positions[16 * 32 + 2 * k];
    EXPECT_EQ(p.x, q.x);
    EXPECT_EQ(p.y, q.y);
    EXPECT_EQ(p.z, 0.0);
  }
}

TEST(ScenegenParts, StuffedTetsHaveTheirHullOnTheExterior) {
  const TriMesh exterior = make_box({-0.5, -1.0, -1.0}, {0.5, 1.0, 1.0}, {10, 20, 20}, 0.3);
  const TetSet set = stuffed_tets(exterior, {{-0.75, -1.25, -1.25}, {0.75, 1.25, 1.25}, {6, 10, 10}}, 0.3);
  EXPECT_GT(min_volume(set), 0.0);
  const TetFaces faces = tet_faces(set);
  EXPECT_EQ(closed(faces.hull), "");
  EXPECT_TRUE(surface_defects(faces.hull).empty());
  const Bvh bvh = build_bvh(exterior.positions, exterior.triangles);
  for (const glm::uvec3& f : faces.hull)
    for (int c = 0; c < 3; ++c) EXPECT_LT(closest_point(bvh, set.positions[f[c]]).squared_distance, 1e-20);
  // Inscribed: a little less than the exterior's volume.
  EXPECT_LT(total_volume(set), mesh_volume(exterior));
  EXPECT_GT(total_volume(set), 0.9 * mesh_volume(exterior));
}

TEST(ScenegenParts, LayoutsAreCleanSolidPieces) {
  const TetSet set = box_lattice({{-1.0, -1.0, 0.0}, {1.0, 1.0, 1.0}, {10, 10, 5}});
  const TetFaces faces = tet_faces(set);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    Rng rng(seed);
    const auto sites = spread_sites(set, 12, rng, [](const glm::dvec3&) { return 1.0; });
    std::vector<int> labels = voronoi_labels(set, sites);
    tidy_labels(set, faces, labels, 8);
    int pieces = 0;
    for (const int l : labels) pieces = std::max(pieces, l + 1);
    EXPECT_GE(pieces, 8) << seed;
    std::vector<std::vector<glm::uvec3>> boundary(pieces);
    for (std::size_t i = 0; i < faces.hull.size(); ++i) boundary[labels[faces.hull_tet[i]]].push_back(faces.hull[i]);
    for (std::size_t i = 0; i < faces.interior.size(); ++i) {
      const int a = labels[faces.interior_tets[i].x], b = labels[faces.interior_tets[i].y];
      const glm::uvec3 f = faces.interior[i];
      if (a != b) boundary[a].push_back(f), boundary[b].push_back({f.x, f.z, f.y});
    }
    for (int p = 0; p < pieces; ++p) {
      EXPECT_EQ(closed(boundary[p]), "") << seed << " piece " << p;
      EXPECT_TRUE(surface_defects(boundary[p]).empty()) << seed << " piece " << p;
    }
    // Pieces are numbered by their lowest tet.
    int seen = -1;
    for (const int l : labels) {
      EXPECT_LE(l, seen + 1);
      seen = std::max(seen, l);
    }
  }
}

// Two sites either side of a weak slab at x = 0.5, off the middle between them: the plain
// Voronoi cells meet at x = 0, the geodesic ones in the slab, as a coarse simulation of that
// material would crack.
TEST(ScenegenParts, GeodesicCellsMeetInWeakMaterial) {
  const TetSet set = box_lattice({{-1.0, -0.5, -0.5}, {1.0, 0.5, 0.5}, {20, 10, 10}});
  const TetFaces faces = tet_faces(set);
  const auto centroid_near = [&](const glm::dvec3& p) {
    glm::dvec3 best = tet_centroid(set, 0);
    for (std::uint32_t t = 1; t < set.tets.size(); ++t)
      if (glm::distance(tet_centroid(set, t), p) < glm::distance(best, p)) best = tet_centroid(set, t);
    return best;
  };
  const std::vector<glm::dvec3> sites = {centroid_near({-0.9, 0.0, 0.0}), centroid_near({0.9, 0.0, 0.0})};
  const CrackCost weak_slab = [](const glm::dvec3& p) { return std::abs(p.x - 0.5) < 0.1 ? 10.0 : 1.0; };
  const auto cut_x = [&](const std::vector<int>& labels) {
    double lo = 1e300, hi = -1e300;
    for (std::size_t i = 0; i < faces.interior.size(); ++i) {
      if (labels[faces.interior_tets[i].x] == labels[faces.interior_tets[i].y]) continue;
      const glm::uvec3 f = faces.interior[i];
      const double x = (set.positions[f.x].x + set.positions[f.y].x + set.positions[f.z].x) / 3.0;
      lo = std::min(lo, x), hi = std::max(hi, x);
    }
    return std::pair(lo, hi);
  };
  const auto [plain_lo, plain_hi] = cut_x(voronoi_labels(set, sites));
  EXPECT_LT(plain_hi, 0.3);
  const std::vector<double> costs = crossing_costs(set, faces, weak_slab);
  ASSERT_EQ(costs.size(), faces.interior.size());
  std::vector<int> labels = geodesic_labels(set, faces, sites, costs);
  const auto [lo, hi] = cut_x(labels);
  EXPECT_GT(lo, 0.35);
  EXPECT_LT(hi, 0.65);
  // Without a weak place the geodesic cells are the lattice's own Voronoi cells.
  const std::vector<double> flat = crossing_costs(set, faces, [](const glm::dvec3&) { return 1.0; });
  const auto [flat_lo, flat_hi] = cut_x(geodesic_labels(set, faces, sites, flat));
  EXPECT_GT(flat_lo, -0.35);
  EXPECT_LT(flat_hi, 0.35);
  tidy_labels(set, faces, labels, 8);
  EXPECT_EQ(cut_x(labels), std::pair(lo, hi));
}

TEST(ScenegenParts, DuplicatesAppearAsAPrefixInSplitOrder) {
  TetSet set = box_lattice({{0.0, 0.0, 0.0}, {3.0, 1.0, 1.0}, {3, 1, 1}});
  const std::size_t n = set.positions.size();
  std::vector<int> group(set.tets.size());
  for (std::uint32_t t = 0; t < set.tets.size(); ++t) group[t] = int(tet_centroid(set, t).x);  // cubes 0, 1, 2
  const Duplication dup = duplicate_vertices(set, group, {10, 30, 1000}, {});
  // Cube 0 leaves first (frame 10) with copies of the x = 1 face; cube 1 next (frame 30) with
  // copies of the x = 2 face; cube 2 never leaves and keeps its originals.
  ASSERT_EQ(set.positions.size(), n + 8);
  EXPECT_EQ(dup.original_count, n);
  for (std::size_t v = n; v < n + 8; ++v) {
    const bool first = v < n + 4;
    EXPECT_EQ(dup.split_frame[v], first ? 10 : 30);
    EXPECT_EQ(dup.group[v], first ? 0 : 1);
    EXPECT_EQ(set.positions[v].x, first ? 1.0 : 2.0);
    EXPECT_EQ(set.positions[v], set.positions[dup.parent[v]]);
    EXPECT_LT(dup.parent[v], n);
  }
  for (std::size_t v = 0; v < n; ++v) EXPECT_EQ(dup.split_frame[v], 0);
  // No vertex is shared between cubes any more.
  std::vector<int> user(set.positions.size(), -1);
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (int c = 0; c < 4; ++c) {
      const std::uint32_t v = set.tets[t][c];
      EXPECT_TRUE(user[v] < 0 || user[v] == group[t]);
      user[v] = group[t];
    }
}

TEST(ScenegenParts, NumbersReadBackExactly) {
  for (const double x : {0.1, 1.0 / 3.0, -2.5e-17, 12345.678901234567, -0.0}) {
    std::string s;
    append_number(s, x);
    EXPECT_EQ(std::stod(s), x == 0.0 ? 0.0 : x) << s;
    EXPECT_EQ(s.find('-') == 0 && x == 0.0, false);
  }
}

}  // namespace
