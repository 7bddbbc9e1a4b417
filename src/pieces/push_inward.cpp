// Fracture triangles that poke out of B, and the inward push of the S vertices that cause it
// (pieces.hpp, step 3b).
#include <algorithm>
#include <cmath>
#include <set>

#include "geom/intersect.hpp"
#include "pieces/pieces_internal.hpp"
#include "util/error.hpp"

namespace fracref::pieces_detail {
namespace {

// Interior sample points of a triangle, barycentric on a grid of this many steps per side.
constexpr int kSampleGrid = 5;
// A rim vertex's inner edge is probed at this fraction of its length, and followed at most
// this far to where it enters B.
constexpr double kRimProbe = 0.02;
constexpr double kMaxRetract = 0.3;
// Self-intersections of S looked at after a push (those not involving a pushed vertex were
// there before and are not this step's to report).
constexpr std::size_t kReportedHits = 256;
constexpr int kPushHalvings = 6;

// How far the inside of triangle (a, b, c) lies outside B at most (0: not beyond `tolerance`),
// and the barycentric weights of the corners there.
double poke_depth(const ExteriorMesh& m, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double tolerance,
                  glm::dvec3& weights) {
  double worst = 0.0;
  for (int i = 1; i < kSampleGrid; ++i)
    for (int j = 1; i + j < kSampleGrid; ++j) {
      const double u = double(i) / kSampleGrid, v = double(j) / kSampleGrid;
      const glm::dvec3 x = (1.0 - u - v) * a + u * b + v * c;
      const double d = std::sqrt(closest_point(m.bvh, x).squared_distance);
      if (d > tolerance && d > worst && !point_in_mesh(m.bvh, x)) worst = d, weights = {1.0 - u - v, u, v};
    }
  return worst;
}

bool outside(const ExteriorMesh& m, const glm::dvec3& x, double tolerance) {
  return std::sqrt(closest_point(m.bvh, x).squared_distance) > tolerance && !point_in_mesh(m.bvh, x);
}

// How far along the inner edge from rim vertex w to v (as a fraction) it enters B, when it
// leaves w outside B; 0 when it leaves w inside.
double entry_along(const ExteriorMesh& m, const glm::dvec3& w, const glm::dvec3& v, double tolerance) {
  if (!outside(m, w + kRimProbe * (v - w), tolerance)) return 0.0;
  double out = kRimProbe, in = -1.0;
  for (double t = 2.0 * kRimProbe; t <= kMaxRetract; t += kRimProbe) {
    if (!outside(m, w + t * (v - w), tolerance)) {
      in = t;
      break;
    }
    out = t;
  }
  if (in < 0.0) return 0.0;  // too far in: not a rim that merely overshoots
  for (int i = 0; i < 48; ++i) {
    const double mid = 0.5 * (out + in);
    (outside(m, w + mid * (v - w), tolerance) ? out : in) = mid;
  }
  return in;
}

}  // namespace

std::uint32_t retract_rim(FractureSurface& s, const ExteriorMesh& m, double tolerance) {
  std::vector<double> along(s.positions.size(), 0.0);
  std::vector<std::uint32_t> toward(s.positions.size(), 0);
  auto at = [&](std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); };
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    if (s.edge_special[e] == kEdgeBoundary) continue;
    for (auto [w, v] : {std::pair{s.edges[e].x, s.edges[e].y}, std::pair{s.edges[e].y, s.edges[e].x}}) {
      if (!(s.vertex_flags[w] & kVertexBoundary) || (s.vertex_flags[v] & kVertexBoundary)) continue;
      const double t = entry_along(m, at(w), at(v), tolerance);
      if (t > along[w]) along[w] = t, toward[w] = v;
    }
  }
  std::uint32_t moved = 0;
  for (std::uint32_t w = 0; w < s.positions.size(); ++w) {
    if (along[w] == 0.0) continue;
    const glm::dvec3 x = at(w) + along[w] * (at(toward[w]) - at(w));
    s.positions[w] = glm::vec4(glm::vec3(closest_point(m.bvh, x).point), s.positions[w].w);
    ++moved;
  }
  return moved;
}

std::map<std::uint32_t, double> poking_vertices(const ExteriorMesh& m, const std::vector<glm::dvec3>& positions,
                                                const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                const std::vector<std::uint8_t>& on_b, std::uint32_t s_vertex_count,
                                                double tolerance) {
  std::map<std::uint32_t, double> out;
  for (const auto& t : triangles) {
    if (!on_b[t[0]] && !on_b[t[1]] && !on_b[t[2]]) continue;  // only S's rim meets B
    glm::dvec3 weights(0.0);
    const double depth = poke_depth(m, positions[t[0]], positions[t[1]], positions[t[2]], tolerance, weights);
    if (depth == 0.0) continue;
    // Moving a corner moves the deepest point by its weight: each corner off B alone would have
    // to go depth / weight.
    for (int k = 0; k < 3; ++k)
      if (t[k] < s_vertex_count && !on_b[t[k]]) out[t[k]] = std::max(out[t[k]], depth / weights[k]);
  }
  return out;
}

namespace {

// The pushed vertices that take part in a self-intersection of S.
std::set<std::uint32_t> pushed_into_itself(const FractureSurface& s, const std::map<std::uint32_t, double>& push) {
  std::vector<glm::dvec3> positions;
  for (const glm::vec4& p : s.positions) positions.emplace_back(glm::vec3(p));
  std::vector<TriangleIds> faces;
  for (const glm::uvec4& f : s.faces) faces.push_back({f.x, f.y, f.z});
  std::set<std::uint32_t> out;
  for (const auto& [f, g] : find_self_intersections(positions, faces, kReportedHits))
    for (std::uint32_t x : {f, g})
      for (std::uint32_t v : faces[x])
        if (push.count(v)) out.insert(v);
  return out;
}

}  // namespace

// A full push can drive a vertex through a nearby sheet of S (two sheets drawn to the same weak
// vein run close). Such a vertex's push is halved until S is clean again, and given up (the
// vertex left where it was) after kPushHalvings; a poke it leaves is reported by the next check.
void push_inward(FractureSurface& s, const ExteriorMesh& m, const std::map<std::uint32_t, double>& push) {
  if (push.empty()) return;
  std::map<std::uint32_t, std::pair<glm::dvec3, glm::dvec3>> start_and_offset;
  for (const auto& [v, distance] : push) {
    const glm::dvec3 p(glm::vec3(s.positions[v]));
    const glm::dvec3 n = m.face_normals[closest_point(m.bvh, p).triangle];
    start_and_offset[v] = {p, -distance * n};
  }
  std::map<std::uint32_t, double> scale;
  for (const auto& [v, so] : start_and_offset) scale[v] = 1.0;
  for (int round = 0; round <= kPushHalvings; ++round) {
    for (const auto& [v, so] : start_and_offset)
      s.positions[v] = glm::vec4(glm::vec3(so.first + scale[v] * so.second), s.positions[v].w);
    const std::set<std::uint32_t> bad = pushed_into_itself(s, push);
    if (bad.empty()) return;
    for (std::uint32_t v : bad) scale[v] = round + 1 < kPushHalvings ? 0.5 * scale[v] : 0.0;
  }
}

}  // namespace fracref::pieces_detail
