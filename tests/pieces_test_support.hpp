#pragma once
// Shared by the pieces tests: hand-made exteriors (boxes, an icosphere), fracture sheets, and the
// checks every piece set must pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "geom/bvh.hpp"
#include "geom/shapes.hpp"
#include "pieces/pieces.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref::pieces_test {

inline MeshSoup to_soup(const TriangleSoup& t) {
  MeshSoup soup;
  soup.positions = t.positions;
  soup.triangles = t.triangles;
  soup.polygons = t.triangles.size();
  for (std::uint32_t i = 0; i < t.triangles.size(); ++i) soup.triangle_polygon.push_back(i);
  return soup;
}

inline MeshSoup box(glm::dvec3 lo, glm::dvec3 hi, int n) { return to_soup(make_box(lo, hi, n)); }

/// An icosahedron subdivided `levels` times, vertices on the unit sphere, outward.
inline MeshSoup icosphere(int levels) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> p = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                               {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (auto& v : p) v = glm::normalize(v);
  std::vector<std::array<std::uint32_t, 3>> t = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      auto [it, inserted] = mid.try_emplace({std::min(a, b), std::max(a, b)}, std::uint32_t(p.size()));
      if (inserted) p.push_back(glm::normalize(p[a] + p[b]));
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& f : t) {
      const std::uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    t = std::move(next);
  }
  return to_soup(TriangleSoup{p, t});
}

/// A grid sheet: vertex (i, j) at at(i, j) for i, j in [0, n), quads split along (i,j)-(i+1,j+1),
/// wound counterclockwise in (i, j): the normal points into `front`.
inline FractureSurface grid_sheet(int n, const std::function<glm::dvec3(int, int)>& at, int front = 1, int back = 0) {
  std::vector<glm::vec4> positions;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) positions.emplace_back(glm::vec3(at(i, j)), 1.0f);
  std::vector<glm::uvec4> faces;
  std::vector<glm::ivec2> pieces;
  auto id = [n](int i, int j) { return std::uint32_t(j * n + i); };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      faces.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1), 0);
      faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1), 0);
      pieces.emplace_back(front, back);
      pieces.emplace_back(front, back);
    }
  return make_fracture_surface(std::move(positions), std::move(faces), std::move(pieces), 2);
}

/// Flat arrays of a fracture sheet, to be combined into one surface.
struct SheetArrays {
  std::vector<glm::vec4> positions;
  std::vector<glm::uvec4> faces;
  std::vector<glm::ivec2> pieces;
};

/// A polar-grid disk in the plane through `centre` with normal `n` (front piece on the normal's
/// side), waved by `amplitude` along n; its rim lies where B is, found by bisection along each
/// direction up to `max_radius` (the section must be star-shaped from the centre), and the rim
/// vertices are projected onto B by closest point and rounded to float, as the refiner does.
inline SheetArrays disk_sheet(const Bvh& bvh, glm::dvec3 centre, glm::dvec3 n, double amplitude, int rings,
                              int segments, double phase, double max_radius = 4.0, glm::ivec2 pieces = {1, 0}) {
  n = glm::normalize(n);
  const glm::dvec3 u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  const glm::dvec3 v = glm::cross(n, u);
  auto rim = [&](double a) {
    const glm::dvec3 d = std::cos(a) * u + std::sin(a) * v;
    double lo = 0.0, hi = max_radius;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (point_in_mesh(bvh, centre + mid * d) ? lo : hi) = mid;
    }
    return lo;
  };
  auto wave = [&](double x, double y) { return amplitude * std::sin(3.0 * x + phase) * std::cos(2.0 * y - phase); };
  SheetArrays out;
  out.positions.emplace_back(glm::vec3(centre + wave(0, 0) * n), 1.0f);
  for (int r = 1; r <= rings; ++r)
    for (int k = 0; k < segments; ++k) {
      const double a = 2.0 * 3.14159265358979 * k / segments + 0.37 * phase;
      const double radius = rim(a) * double(r) / rings;
      const double x = radius * std::cos(a), y = radius * std::sin(a);
      glm::dvec3 p = centre + x * u + y * v + wave(x, y) * n * (r == rings ? 0.3 : 1.0);
      if (r == rings) p = closest_point(bvh, p).point;
      out.positions.emplace_back(glm::vec3(p), 1.0f);
    }
  auto id = [segments](int r, int k) { return std::uint32_t(1 + (r - 1) * segments + (k % segments)); };
  for (int k = 0; k < segments; ++k) out.faces.emplace_back(0, id(1, k), id(1, k + 1), 0);
  for (int r = 1; r < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      out.faces.emplace_back(id(r, k), id(r + 1, k), id(r + 1, k + 1), 0);
      out.faces.emplace_back(id(r, k), id(r + 1, k + 1), id(r, k + 1), 0);
    }
  out.pieces.assign(out.faces.size(), pieces);
  return out;
}

/// One fracture surface from several sheets (their vertices kept apart).
inline FractureSurface combine_sheets(const std::vector<SheetArrays>& sheets, int piece_count) {
  SheetArrays all;
  for (const SheetArrays& s : sheets) {
    const std::uint32_t base = std::uint32_t(all.positions.size());
    all.positions.insert(all.positions.end(), s.positions.begin(), s.positions.end());
    for (glm::uvec4 f : s.faces) all.faces.emplace_back(f.x + base, f.y + base, f.z + base, 0);
    all.pieces.insert(all.pieces.end(), s.pieces.begin(), s.pieces.end());
  }
  return make_fracture_surface(std::move(all.positions), std::move(all.faces), std::move(all.pieces), piece_count);
}

/// A torus around the z axis (major radius R, tube radius r), nu x nv quads, outward.
inline MeshSoup torus(double R, double r, int nu, int nv) {
  TriangleSoup t;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2.0 * 3.14159265358979 * i / nu, v = 2.0 * 3.14159265358979 * j / nv;
      t.positions.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
    }
  auto id = [&](int i, int j) { return std::uint32_t(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      t.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return to_soup(t);
}

/// The closed surface of a set of unit voxels (faces between a filled and an empty cell, two
/// triangles each, outward). \pre no two filled voxels touch along an edge only.
inline MeshSoup voxel_surface(const std::set<std::array<int, 3>>& cells, double size) {
  TriangleSoup t;
  std::map<std::array<int, 3>, std::uint32_t> ids;
  auto vertex = [&](std::array<int, 3> p) {
    auto [it, inserted] = ids.try_emplace(p, std::uint32_t(t.positions.size()));
    if (inserted) t.positions.emplace_back(size * p[0], size * p[1], size * p[2]);
    return it->second;
  };
  for (const auto& c : cells)
    for (int axis = 0; axis < 3; ++axis)
      for (int dir : {-1, 1}) {
        std::array<int, 3> n = c;
        n[axis] += dir;
        if (cells.count(n)) continue;
        const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        std::array<int, 3> base = c;
        if (dir > 0) base[axis] += 1;
        std::array<std::array<int, 3>, 4> q;
        for (int k = 0; k < 4; ++k) {
          q[k] = base;
          q[k][a1] += (k == 1 || k == 2);
          q[k][a2] += (k >= 2);
        }
        // q0 q1 q2 q3 runs counterclockwise around +axis; reverse for the -axis side.
        std::array<std::uint32_t, 4> v{vertex(q[0]), vertex(q[1]), vertex(q[2]), vertex(q[3])};
        if (dir < 0) std::swap(v[1], v[3]);
        t.triangles.push_back({v[0], v[1], v[2]});
        t.triangles.push_back({v[0], v[2], v[3]});
      }
  return to_soup(t);
}

inline double volume(const std::vector<glm::dvec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& tris) {
  double sum = 0.0;
  for (const auto& t : tris) sum += glm::dot(positions[t[0]], glm::cross(positions[t[1]], positions[t[2]]));
  return sum / 6.0;
}

/// V - E + F of one piece (2 for a ball).
inline long euler_characteristic(const PieceSet::Piece& piece) {
  std::set<std::uint32_t> v;
  std::set<std::pair<std::uint32_t, std::uint32_t>> e;
  for (const auto& t : piece.triangles)
    for (int k = 0; k < 3; ++k) {
      v.insert(t[k]);
      e.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
    }
  return long(v.size()) - long(e.size()) + long(piece.triangles.size());
}

/// Every fracture triangle lies in exactly two pieces, on the same three vertex ids, wound
/// oppositely: neighbouring pieces share their fracture vertices exactly.
inline void expect_fracture_shared(const PieceSet& set) {
  std::map<std::array<std::uint32_t, 3>, std::vector<std::pair<std::size_t, bool>>> seen;
  for (std::size_t p = 0; p < set.pieces.size(); ++p)
    for (std::size_t t = 0; t < set.pieces[p].triangles.size(); ++t) {
      if (!set.pieces[p].inside[t]) continue;
      auto tri = set.pieces[p].triangles[t];
      const auto lowest = std::min_element(tri.begin(), tri.end());
      std::rotate(tri.begin(), lowest, tri.end());
      const bool flipped = tri[1] > tri[2];
      if (flipped) std::swap(tri[1], tri[2]);
      seen[tri].emplace_back(p, flipped);
    }
  for (const auto& [tri, uses] : seen) {
    ASSERT_EQ(uses.size(), 2u) << "fracture triangle " << tri[0] << " " << tri[1] << " " << tri[2];
    EXPECT_NE(uses[0].first, uses[1].first);
    EXPECT_NE(uses[0].second, uses[1].second);
  }
}

/// The output contract: check_pieces passes with 2000 points, volumes within 0.1%, every piece
/// a ball (Euler characteristic 2), fracture triangles shared.
inline PieceReport expect_valid_pieces(const PieceSet& set, const MeshSoup& exterior) {
  PieceCheckOptions options;
  options.sample_points = 2000;
  const PieceReport report = check_pieces(set, exterior, options);
  std::string failures;
  for (const auto& f : report.failures) failures += f + "\n";
  EXPECT_TRUE(report.ok()) << failures;
  EXPECT_LT(report.volume_relative_error, 1e-3);
  EXPECT_EQ(report.points_tested, 2000u);
  EXPECT_EQ(report.points_in_no_piece, 0u);
  EXPECT_EQ(report.points_in_several_pieces, 0u);
  for (std::size_t p = 0; p < set.pieces.size(); ++p) {
    EXPECT_TRUE(report.pieces[p].closed()) << "piece " << p;
    EXPECT_TRUE(report.pieces[p].edge_manifold()) << "piece " << p;
    EXPECT_TRUE(report.pieces[p].outward()) << "piece " << p;
    EXPECT_EQ(report.pieces[p].self_intersections, 0u) << "piece " << p;
    EXPECT_EQ(euler_characteristic(set.pieces[p]), 2) << "piece " << p;
  }
  expect_fracture_shared(set);
  return report;
}

}  // namespace fracref::pieces_test
