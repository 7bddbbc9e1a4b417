// Fracture triangles that poke out of B, and the inward push of the S vertices that cause it
// (pieces.hpp, step 3b).
#include <algorithm>
#include <cmath>
#include <set>

#include "geom/bvh.hpp"
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
constexpr int kPushHalvings = 6;

// How far the inside of triangle (a, b, c) lies outside B at most (0: not beyond `tolerance`),
// the barycentric weights of the corners there and the unit direction from there back to B.
double poke_depth(const ExteriorMesh& m, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double tolerance,
                  glm::dvec3& weights, glm::dvec3& back) {
  double worst = 0.0;
  for (int i = 1; i < kSampleGrid; ++i)
    for (int j = 1; i + j < kSampleGrid; ++j) {
      const double u = double(i) / kSampleGrid, v = double(j) / kSampleGrid;
      const glm::dvec3 x = (1.0 - u - v) * a + u * b + v * c;
      const ClosestPoint q = closest_point(m.bvh, x);
      const double d = std::sqrt(q.squared_distance);
      if (d > tolerance && d > worst && !point_in_mesh(m.bvh, x)) worst = d, weights = {1.0 - u - v, u, v}, back = (q.point - x) / d;
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

// The faces of S, a tree over boxes that hold each face wherever the moves of `offset` may
// take it (a moved corner goes from its start toward start + offset; float rounding of a point
// between two floats stays between them), and the faces with a moved corner.
struct MoveCheck {
  std::vector<TriangleIds> faces;
  std::vector<std::uint32_t> moved_faces;
  Bvh tree;
};

MoveCheck prepare_move_check(const FractureSurface& s, const std::map<std::uint32_t, glm::dvec3>& offset) {
  MoveCheck c;
  c.faces = face_triangles(s);
  std::vector<Aabb> boxes(c.faces.size());
  for (std::uint32_t f = 0; f < c.faces.size(); ++f) {
    bool moved = false;
    for (std::uint32_t v : c.faces[f]) {
      const glm::vec3 start(s.positions[v]);
      boxes[f].expand(glm::dvec3(start));
      if (const auto it = offset.find(v); it != offset.end()) {
        boxes[f].expand(stored_position(glm::dvec3(start) + it->second));
        moved = true;
      }
    }
    if (moved) c.moved_faces.push_back(f);
  }
  c.tree = build_bvh(boxes);
  return c;
}

// The moved vertices that take part in a self-intersection of S (at a face with a moved corner:
// the others were there before the move and are not its to report).
std::set<std::uint32_t> moved_into_itself(const FractureSurface& s, const MoveCheck& c,
                                          const std::map<std::uint32_t, glm::dvec3>& moved) {
  const std::vector<glm::dvec3> positions = double_positions(s);
  std::set<std::uint32_t> out;
  std::vector<std::uint32_t> hits;
  for (std::uint32_t f : c.moved_faces) {
    Aabb box;
    for (std::uint32_t v : c.faces[f]) box.expand(positions[v]);
    hits.clear();
    query_box(c.tree, box, hits);
    for (std::uint32_t g : hits) {
      if (g == f || !mesh_faces_intersect(positions, c.faces[std::min(f, g)], c.faces[std::max(f, g)])) continue;
      for (std::uint32_t x : {f, g})
        for (std::uint32_t v : c.faces[x])
          if (moved.count(v)) out.insert(v);
    }
  }
  return out;
}

// Moves each vertex of `offset` by it; a vertex whose move makes S intersect itself at one of
// its faces has its move halved until S is clean, and after `halvings` halvings stays where it
// was. Returns how many vertices moved.
std::uint32_t move_clear_of_itself(FractureSurface& s, const std::map<std::uint32_t, glm::dvec3>& offset, int halvings) {
  if (offset.empty()) return 0;
  const MoveCheck check = prepare_move_check(s, offset);
  std::map<std::uint32_t, std::pair<glm::dvec3, double>> start_and_scale;
  for (const auto& [v, d] : offset) start_and_scale[v] = {glm::dvec3(glm::vec3(s.positions[v])), 1.0};
  for (int round = 0; round <= halvings + 1; ++round) {
    for (const auto& [v, ss] : start_and_scale)
      s.positions[v] = glm::vec4(glm::vec3(ss.first + ss.second * offset.at(v)), s.positions[v].w);
    const std::set<std::uint32_t> bad = moved_into_itself(s, check, offset);
    if (bad.empty()) break;
    for (std::uint32_t v : bad) start_and_scale[v].second = round < halvings ? 0.5 * start_and_scale[v].second : 0.0;
  }
  std::uint32_t moved = 0;
  for (const auto& [v, ss] : start_and_scale) moved += ss.second > 0.0;
  return moved;
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
  std::map<std::uint32_t, glm::dvec3> offset;
  for (std::uint32_t w = 0; w < s.positions.size(); ++w) {
    if (along[w] == 0.0) continue;
    const glm::dvec3 x = at(w) + along[w] * (at(toward[w]) - at(w));
    offset[w] = closest_point(m.bvh, x).point - at(w);
  }
  // A rim vertex must stay on B, so a retraction is made whole or not at all.
  return move_clear_of_itself(s, offset, 0);
}

std::map<std::uint32_t, Push> poking_vertices(const ExteriorMesh& m, const std::vector<glm::dvec3>& positions,
                                              const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                              const std::vector<std::uint8_t>& on_b, std::uint32_t s_vertex_count,
                                              double tolerance) {
  std::map<std::uint32_t, Push> out;
  for (const auto& t : triangles) {
    if (!on_b[t[0]] && !on_b[t[1]] && !on_b[t[2]]) continue;  // only S's rim meets B
    glm::dvec3 weights(0.0), back(0.0);
    const double depth = poke_depth(m, positions[t[0]], positions[t[1]], positions[t[2]], tolerance, weights, back);
    if (depth == 0.0) continue;
    // Moving a corner moves the deepest point by its weight: each corner off B alone would have
    // to go depth / weight.
    for (int k = 0; k < 3; ++k) {
      if (t[k] >= s_vertex_count || on_b[t[k]]) continue;
      Push& p = out[t[k]];
      if (depth / weights[k] > p.distance) p = {depth / weights[k], back};
    }
  }
  return out;
}

// A full push can drive a vertex through a nearby sheet of S (two sheets drawn to the same weak
// vein run close): such a push is halved, and given up after kPushHalvings; a poke it leaves is
// reported by the next check.
void push_inward(FractureSurface& s, const ExteriorMesh& m, const std::map<std::uint32_t, Push>& push) {
  std::map<std::uint32_t, glm::dvec3> offset;
  for (const auto& [v, p] : push) {
    glm::dvec3 direction = p.direction;
    if (direction == glm::dvec3(0.0)) direction = -m.face_normals[closest_point(m.bvh, glm::dvec3(glm::vec3(s.positions[v]))).triangle];
    offset[v] = p.distance * direction;
  }
  move_clear_of_itself(s, offset, kPushHalvings);
}

// Relaxing flattens a fold that the flow left sharp next to the rim: the traces bend the rim
// faces toward B, and a neighbour folded onto them is then crossed.
void relax_toward_neighbours(FractureSurface& s, const std::map<std::uint32_t, double>& relax) {
  std::map<std::uint32_t, glm::dvec3> offset;
  for (const auto& [v, fraction] : relax) {
    std::set<std::uint32_t> ring;
    for (std::uint32_t k = s.vf_offsets[v]; k < s.vf_offsets[v + 1]; ++k)
      for (int c = 0; c < 3; ++c)
        if (s.faces[s.vf_faces[k]][c] != v) ring.insert(s.faces[s.vf_faces[k]][c]);
    if (ring.empty()) continue;
    glm::dvec3 centroid(0.0);
    for (std::uint32_t w : ring) centroid += glm::dvec3(glm::vec3(s.positions[w]));
    offset[v] = fraction * (centroid / double(ring.size()) - glm::dvec3(glm::vec3(s.positions[v])));
  }
  move_clear_of_itself(s, offset, kPushHalvings);
}

}  // namespace fracref::pieces_detail
