// trim_to_exterior (rim/trim_to_exterior.hpp).
#include "rim/trim_to_exterior.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numeric>
#include <set>

#include "geom/bvh.hpp"
#include "geom/predicates.hpp"
#include "rim/cut_triangulation.hpp"
#include "util/error.hpp"

namespace fracref::rim {
namespace {

using Pair = std::pair<std::uint32_t, std::uint32_t>;

Pair undirected(std::uint32_t a, std::uint32_t b) { return a < b ? Pair{a, b} : Pair{b, a}; }

// Weights of x (near the plane of a, b, c) on the corners, clamped to the triangle.
glm::dvec3 clamped_weights(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& x) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double n2 = glm::dot(n, n);
  if (!(n2 > 0.0)) return glm::dvec3(1.0 / 3.0);
  glm::dvec3 w(0.0);
  w.y = glm::dot(glm::cross(x - a, c - a), n) / n2;
  w.z = glm::dot(glm::cross(b - a, x - a), n) / n2;
  w.x = 1.0 - w.y - w.z;
  w = glm::max(w, glm::dvec3(0.0));
  return w / (w.x + w.y + w.z);
}

class Trimmer {
 public:
  Trimmer(FractureSurface& s, const ExteriorMesh& m, RimOnB& rim, std::vector<EmbeddedVertex>& added)
      : s_(s), m_(m), rim_(rim), added_(added) {}

  TrimStats run() {
    const std::size_t nf = s_.faces.size();
    rim_.at.resize(s_.positions.size());
    rim_.on_b.resize(s_.positions.size(), 0);
    for (std::uint32_t v = 0; v < s_.positions.size(); ++v)
      p_.push_back(on_rim(v) ? rim_.at[v].point : glm::dvec3(glm::vec3(s_.positions[v])));
    // 1. the segments F ∩ T of every face
    segments_.resize(nf);
    std::vector<std::uint32_t> near;
    for (std::uint32_t f = 0; f < nf; ++f) {
      Aabb box;
      for (int k = 0; k < 3; ++k) box.expand(p_[s_.faces[f][k]]);
      near.clear();
      query_box(m_.bvh, box, near);
      std::sort(near.begin(), near.end());
      for (std::uint32_t t : near) intersect(f, t);
    }
    // 2. each face with points on it triangulated along its segments
    std::vector<std::vector<std::array<std::uint32_t, 3>>> cells(nf);
    std::vector<char> cut(nf, 0);
    for (std::uint32_t f = 0; f < nf; ++f) {
      bool any = !segments_[f].empty() || y_of_face_.count(f);
      for (int k = 0; k < 3; ++k) any = any || edge_points_.count(s_.face_edges[3 * f + k]);
      if (!any) {
        cells[f].push_back({s_.faces[f].x, s_.faces[f].y, s_.faces[f].z});
        continue;
      }
      cut[f] = 1;
      cells[f] = triangulate(f);
    }
    // 3. regions across the edges that are not segments, and their sides
    std::vector<std::pair<std::uint32_t, std::uint32_t>> cell_ids;  // (face, index)
    std::vector<std::uint32_t> first(nf + 1, 0);
    for (std::uint32_t f = 0; f < nf; ++f) first[f + 1] = first[f] + std::uint32_t(cells[f].size());
    parent_.resize(first[nf]);
    std::iota(parent_.begin(), parent_.end(), 0u);
    std::map<Pair, std::uint32_t> edge_cell;
    for (std::uint32_t f = 0; f < nf; ++f)
      for (std::uint32_t i = 0; i < cells[f].size(); ++i)
        for (int k = 0; k < 3; ++k) {
          const Pair e = undirected(cells[f][i][k], cells[f][i][(k + 1) % 3]);
          if (segment_face_.count(e)) continue;
          auto [it, inserted] = edge_cell.emplace(e, first[f] + i);
          if (!inserted) unite(it->second, first[f] + i);
        }
    std::vector<int> votes_in(first[nf], 0), votes_out(first[nf], 0);
    for (std::uint32_t f = 0; f < nf; ++f)
      for (std::uint32_t i = 0; i < cells[f].size(); ++i) {
        const auto& c = cells[f][i];
        const glm::dvec3 centroid = (p_[c[0]] + p_[c[1]] + p_[c[2]]) / 3.0;
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t t = bounding_triangle(c[k], c[(k + 1) % 3]);
          if (t == kNone) continue;
          const auto& tri = m_.triangles[t];
          const int o = orient3d(m_.positions[tri[0]], m_.positions[tri[1]], m_.positions[tri[2]], centroid);
          const std::uint32_t r = find(first[f] + i);
          if (o > 0) ++votes_in[r];
          else if (o < 0) ++votes_out[r];
        }
      }
    std::vector<char> inside(first[nf], 1);
    for (std::uint32_t f = 0; f < nf; ++f)
      for (std::uint32_t i = 0; i < cells[f].size(); ++i) {
        const std::uint32_t id = first[f] + i, r = find(id);
        if (r != id) continue;
        if (votes_in[r] == votes_out[r] && votes_in[r] > 0) {
          const auto& c = cells[f][i];
          inside[r] = point_in_mesh(m_.bvh, (p_[c[0]] + p_[c[1]] + p_[c[2]]) / 3.0);
        } else {
          inside[r] = votes_in[r] >= votes_out[r];
        }
      }
    // 4. the kept faces
    TrimStats stats;
    std::vector<glm::uvec4> faces;
    std::vector<glm::ivec2> pieces;
    for (std::uint32_t f = 0; f < nf; ++f) {
      stats.cut_faces += cut[f];
      bool dropped = false;
      for (std::uint32_t i = 0; i < cells[f].size(); ++i) {
        if (!inside[find(first[f] + i)] || lies_on_b(cells[f][i])) {
          dropped = true;
          continue;
        }
        const auto& c = cells[f][i];
        faces.push_back(glm::uvec4(c[0], c[1], c[2], 0u));
        pieces.push_back(s_.face_pieces[f]);
      }
      stats.removed_faces += dropped;
    }
    stats.new_vertices = new_vertices_;
    s_.faces = std::move(faces);
    s_.face_pieces = std::move(pieces);
    rebuild_adjacency(s_);
    for (std::uint32_t v = 0; v < s_.positions.size(); ++v)
      if (s_.vf_offsets[v] == s_.vf_offsets[v + 1]) rim_.on_b[v] = 0;
    if (std::string broken = validate(s_); !broken.empty())
      throw RunError("trimming the fracture surface to the exterior made it invalid (an internal error; please report it): " +
                     broken);
    return stats;
  }

 private:
  // A triangle whose corners are all on B and whose centroid is on B too (a flap folded onto B)
  // lies on B: it bounds no piece, and a piece built with it would not be a manifold.
  bool lies_on_b(const std::array<std::uint32_t, 3>& c) const {
    for (int k = 0; k < 3; ++k)
      if (!(c[k] < p_.size() && (c[k] >= s_.positions.size() || on_rim(c[k])))) return false;
    const glm::dvec3 centroid = (p_[c[0]] + p_[c[1]] + p_[c[2]]) / 3.0;
    return closest_point(m_.bvh, centroid).squared_distance <= std::pow(1e-9 * m_.diagonal, 2);
  }

  bool on_rim(std::uint32_t v) const { return v < rim_.on_b.size() && rim_.on_b[v]; }
  bool held(std::uint32_t v, std::uint32_t t) const { return on_rim(v) && location_in_face(m_, rim_.at[v], t); }
  // Whether rim vertex v lies on the closed B edge g.
  bool on_b_edge(std::uint32_t v, std::uint32_t g) const {
    if (!on_rim(v)) return false;
    const Location& loc = rim_.at[v];
    if (loc.kind == Location::kEdge) return loc.id == g;
    if (loc.kind == Location::kVertex) return loc.id == m_.edges[g].x || loc.id == m_.edges[g].y;
    return false;
  }
  glm::dvec3 corner(std::uint32_t t, int k) const { return m_.positions[m_.triangles[t][std::size_t(k)]]; }
  // Side of x for the plane of B triangle t: 1 inside B's side (or on the plane), -1 outside.
  int side(std::uint32_t t, const glm::dvec3& x) const { return orient3d(corner(t, 0), corner(t, 1), corner(t, 2), x) >= 0 ? 1 : -1; }

  std::uint32_t new_vertex(const Location& loc, const std::array<std::uint32_t, 3>& parents, const glm::dvec3& w) {
    const std::uint32_t id = std::uint32_t(s_.positions.size());
    s_.positions.push_back(glm::vec4(glm::vec3(loc.point), 1.0f));
    rim_.at.push_back(loc);
    rim_.on_b.push_back(1);
    p_.push_back(loc.point);
    added_.push_back({id, parents, w});
    ++new_vertices_;
    return id;
  }

  // The vertex where S edge e crosses B triangle t (the open segment through the open triangle),
  // or kNone.
  std::uint32_t edge_crossing(std::uint32_t e, std::uint32_t t) {
    const auto key = std::make_pair(e, t);
    if (auto it = x_.find(key); it != x_.end()) return it->second;
    std::uint32_t id = kNone;
    const std::uint32_t a = s_.edges[e].x, b = s_.edges[e].y;
    if (!held(a, t) && !held(b, t) && side(t, p_[a]) != side(t, p_[b])) {
      int o[3];
      for (int k = 0; k < 3; ++k) o[k] = orient3d(p_[a], p_[b], corner(t, k), corner(t, (k + 1) % 3));
      int zeros = 0, sign = 0;
      bool mixed = false;
      for (int k = 0; k < 3; ++k) {
        if (o[k] == 0) ++zeros;
        else if (sign == 0) sign = o[k];
        else mixed = mixed || o[k] != sign;
      }
      if (!mixed && zeros < 3) {
        const glm::dvec3 n = glm::cross(corner(t, 1) - corner(t, 0), corner(t, 2) - corner(t, 0));
        const double da = glm::dot(n, p_[a] - corner(t, 0)), db = glm::dot(n, p_[b] - corner(t, 0));
        const double u = std::clamp(da / (da - db), 0.0, 1.0);
        const glm::dvec3 x = p_[a] + u * (p_[b] - p_[a]);
        // Through the open triangle: its own point. Exactly through a side (one zero) or a corner
        // (two) of T: the point is on that B edge or vertex, shared by the triangles around it.
        Location loc;
        std::array<std::uint32_t, 2> feature{kNone, kNone};
        if (zeros == 0) {
          loc = location_from_weights(m_, t, clamped_weights(corner(t, 0), corner(t, 1), corner(t, 2), x));
        } else if (zeros == 1) {
          const int k = o[0] == 0 ? 0 : (o[1] == 0 ? 1 : 2);
          const std::uint32_t g = m_.face_edges[t][std::size_t(k)];
          const glm::dvec3 c = m_.positions[m_.edges[g].x], d = m_.positions[m_.edges[g].y];
          const double along = std::clamp(glm::dot(x - c, d - c) / glm::dot(d - c, d - c), 1e-12, 1.0 - 1e-12);
          loc = edge_location(m_, g, along);
          feature = {0u, g};
        } else {
          const int k = o[0] != 0 ? 2 : (o[1] != 0 ? 0 : 1);  // the corner between the two zero sides
          loc = vertex_location(m_, m_.triangles[t][std::size_t(k)]);
          feature = {1u, loc.id};
        }
        if (feature[0] == kNone) {
          id = new_vertex(loc, {a, b, b}, glm::dvec3(1.0 - u, u, 0.0));
          edge_points_[e].push_back({u, id});
        } else if (auto it = on_feature_.find({e, feature[0], feature[1]}); it != on_feature_.end()) {
          id = it->second;
        } else {
          id = new_vertex(loc, {a, b, b}, glm::dvec3(1.0 - u, u, 0.0));
          edge_points_[e].push_back({u, id});
          on_feature_[{e, feature[0], feature[1]}] = id;
        }
      }
    }
    x_[key] = id;
    return id;
  }

  // The vertex where B edge g crosses the open face f of S, or kNone.
  std::uint32_t face_crossing(std::uint32_t g, std::uint32_t f) {
    const auto key = std::make_pair(g, f);
    if (auto it = y_.find(key); it != y_.end()) return it->second;
    std::uint32_t id = kNone;
    const glm::uvec4 F = s_.faces[f];
    const glm::dvec3 c = m_.positions[m_.edges[g].x], d = m_.positions[m_.edges[g].y];
    const glm::dvec3 q[3] = {p_[F.x], p_[F.y], p_[F.z]};
    bool touching = false;
    for (int k = 0; k < 3; ++k) touching = touching || on_b_edge(F[k], g);
    if (!touching) {
      const int sc = orient3d(q[0], q[1], q[2], c) >= 0 ? 1 : -1, sd = orient3d(q[0], q[1], q[2], d) >= 0 ? 1 : -1;
      if (sc != sd) {
        int o[3];
        for (int k = 0; k < 3; ++k) o[k] = orient3d(c, d, q[k], q[(k + 1) % 3]);
        if (o[0] != 0 && o[0] == o[1] && o[1] == o[2]) {
          const glm::dvec3 n = glm::cross(q[1] - q[0], q[2] - q[0]);
          const double dc = glm::dot(n, c - q[0]), dd = glm::dot(n, d - q[0]);
          const double u = std::clamp(dc / (dc - dd), 1e-12, 1.0 - 1e-12);
          const Location loc = edge_location(m_, g, u);
          const glm::dvec3 w = clamped_weights(q[0], q[1], q[2], loc.point);
          id = new_vertex(loc, {F.x, F.y, F.z}, w);
          y_of_face_[f].push_back(id);
          y_weights_[id] = w;
        }
      }
    }
    y_[key] = id;
    return id;
  }

  // The segment F ∩ T, when it is one (rim vertices of F held by T count as on T's plane).
  void intersect(std::uint32_t f, std::uint32_t t) {
    const glm::uvec4 F = s_.faces[f];
    int holds = 0;
    std::uint32_t held_corner = kNone;
    for (int k = 0; k < 3; ++k)
      if (held(F[k], t)) ++holds, held_corner = F[k];
    if (holds >= 2) return;  // F's edge lies in T (a rim edge or a chord on B): its boundary
    // quick rejections: F on one side of T's plane, or T on one side of F's plane
    int plus = 0, minus = 0;
    for (int k = 0; k < 3; ++k)
      if (F[k] != held_corner) (side(t, p_[F[k]]) > 0 ? plus : minus)++;
    if (plus == 0 || minus == 0) return;
    std::vector<std::uint32_t> ends;
    if (held_corner != kNone) ends.push_back(held_corner);
    for (int k = 0; k < 3; ++k)
      if (std::uint32_t x = edge_crossing(s_.face_edges[3 * f + k], t); x != kNone) ends.push_back(x);
    for (int k = 0; k < 3; ++k)
      if (std::uint32_t y = face_crossing(m_.face_edges[t][std::size_t(k)], f); y != kNone) ends.push_back(y);
    if (ends.size() < 2) return;
    if (ends.size() > 2 || ends[0] == ends[1])
      throw RunError("fracture surface face " + std::to_string(f) + " (" + std::to_string(F.x) + ", " + std::to_string(F.y) +
                     ", " + std::to_string(F.z) + ") meets exterior triangle " + std::to_string(t) + " near " +
                     format_point(p_[F.x]) + " in " + std::to_string(ends.size()) +
                     " points: a degenerate intersection the trim cannot cut along");
    segments_[f].push_back({ends[0], ends[1]});
    segment_face_.emplace(undirected(ends[0], ends[1]), t);
  }

  // Face f triangulated in its barycentric plane along its segments: triangles of global ids,
  // wound as f.
  std::vector<std::array<std::uint32_t, 3>> triangulate(std::uint32_t f) {
    const glm::uvec4 F = s_.faces[f];
    CutTriangle in;
    std::map<std::uint32_t, std::uint32_t> local;
    std::vector<std::uint32_t> global;
    auto add = [&](std::uint32_t v, const glm::dvec2& uv) {
      local[v] = std::uint32_t(global.size());
      global.push_back(v);
      in.uv.push_back(uv);
      in.xyz.push_back(p_[v]);
      return local[v];
    };
    add(F.x, {0.0, 0.0});
    add(F.y, {1.0, 0.0});
    add(F.z, {0.0, 1.0});
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t e = s_.face_edges[3 * f + k];
      const bool forward = s_.edges[e].x == F[k];
      auto it = edge_points_.find(e);
      if (it == edge_points_.end()) continue;
      std::vector<std::pair<double, std::uint32_t>> points = it->second;
      for (auto& [u, v] : points) u = forward ? u : 1.0 - u;
      std::sort(points.begin(), points.end());
      for (const auto& [u, v] : points)
        in.side_points[std::size_t(k)].push_back(add(v, side_uv(k, forward, forward ? u : 1.0 - u)));
    }
    if (auto it = y_of_face_.find(f); it != y_of_face_.end())
      for (std::uint32_t v : it->second) {
        const glm::dvec3 w = y_weights_.at(v);
        in.interior.push_back(add(v, {w.y, w.z}));
      }
    for (const auto& [a, b] : segments_[f]) in.constraints.push_back({local.at(a), local.at(b)});
    std::vector<std::array<std::uint32_t, 3>> tris;
    try {
      tris = triangulate_cut_triangle(in);
    } catch (const RunError& err) {
      throw RunError("fracture surface face " + std::to_string(f) + " near " + format_point(p_[F.x]) +
                     " cannot be cut along the exterior (" + std::to_string(segments_[f].size()) + " segments): " + err.what());
    }
    for (auto& t : tris)
      for (auto& v : t) v = global[v];
    return tris;
  }

  // The B triangle a cell edge lies in when it bounds S's part inside B there: a segment F ∩ T,
  // or a rim edge of S in one triangle only (not along a B edge); else kNone.
  std::uint32_t bounding_triangle(std::uint32_t a, std::uint32_t b) const {
    if (auto it = segment_face_.find(undirected(a, b)); it != segment_face_.end()) return it->second;
    if (a >= rim_boundary_limit() || b >= rim_boundary_limit() || !on_rim(a) || !on_rim(b)) return kNone;
    const std::uint32_t e = find_edge(s_, a, b);
    if (e == kNoEdge || s_.edge_special[e] != kEdgeBoundary) return kNone;
    std::uint32_t found = kNone;
    for (std::uint32_t t : location_faces(m_, rim_.at[a]))
      if (location_in_face(m_, rim_.at[b], t)) {
        if (found != kNone) return kNone;
        found = t;
      }
    return found;
  }
  std::size_t rim_boundary_limit() const { return s_.vf_offsets.size() - 1; }

  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

  FractureSurface& s_;
  const ExteriorMesh& m_;
  RimOnB& rim_;
  std::vector<EmbeddedVertex>& added_;
  std::vector<glm::dvec3> p_;  // per vertex: its point (a rim vertex's location's)
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> x_, y_;  // (S edge, T), (B edge, F) -> vertex
  std::map<std::uint32_t, std::vector<std::pair<double, std::uint32_t>>> edge_points_;  // S edge -> (u from .x, vertex)
  std::map<std::uint32_t, std::vector<std::uint32_t>> y_of_face_;
  std::map<std::array<std::uint32_t, 3>, std::uint32_t> on_feature_;  // (S edge, 0: B edge / 1: B vertex, id) -> vertex
  std::map<std::uint32_t, glm::dvec3> y_weights_;  // B-edge point -> its weights in its face
  std::vector<std::vector<Pair>> segments_;  // per face
  std::map<Pair, std::uint32_t> segment_face_;  // segment -> its B triangle
  std::vector<std::uint32_t> parent_;
  std::uint32_t new_vertices_ = 0;
};

}  // namespace

TrimStats trim_to_exterior(FractureSurface& s, const ExteriorMesh& m, RimOnB& rim, std::vector<EmbeddedVertex>& added) {
  return Trimmer(s, m, rim, added).run();
}

}  // namespace fracref::rim
