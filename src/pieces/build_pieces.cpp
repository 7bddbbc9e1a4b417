// build_pieces: vertices, cut, patches, merge (pieces.hpp).
#include <algorithm>
#include <cmath>
#include <map>

#include "geom/bvh.hpp"
#include "pieces/pieces.hpp"
#include "pieces/pieces_internal.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using namespace pieces_detail;
using Tri = std::array<std::uint32_t, 3>;
using DirectedEdge = std::pair<std::uint32_t, std::uint32_t>;

std::string vertex_pair(std::uint32_t a, std::uint32_t b) { return std::to_string(a) + "-" + std::to_string(b); }

// S with its derived arrays rebuilt (a caller may hand it over stale), if its invariants hold.
FractureSurface checked(const FractureSurface& s) {
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const glm::uvec4 t = s.faces[f];
    const bool bad = t.x >= s.positions.size() || t.y >= s.positions.size() || t.z >= s.positions.size() ||
                     t.x == t.y || t.y == t.z || t.z == t.x;
    if (bad) throw RunError("the fracture surface is not valid: " + validate(s));
  }
  FractureSurface copy = s;
  rebuild_adjacency(copy);
  const std::string problem = validate_rebuilt(copy);  // validate() would rebuild it a second time
  if (!problem.empty()) throw RunError("the fracture surface is not valid: " + problem);
  return copy;
}

class PieceBuilder {
 public:
  PieceBuilder(const FractureSurface& s, const ExteriorMesh& m, const rim::RimOnB& rim, const PieceOptions& options)
      : m_(m), rim_(rim), options_(options), s_(s) {}

  PieceSet run() {
    if (const std::string missing = rim::find_unembedded_rim(s_, m_, rim_); !missing.empty())
      throw RunError("the pieces cannot be made: " + missing + " (the rim must be embedded in the exterior first)");
    add_s_vertices();
    add_exterior_vertices();
    add_rim_segments();
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e)
      if (s_.edge_special[e] != kEdgeBoundary && cut_.on_b[s_.edges[e].x] && cut_.on_b[s_.edges[e].y])
        cut_.chords.insert({std::min(s_.edges[e].x, s_.edges[e].y), std::max(s_.edges[e].x, s_.edges[e].y)});
    b_triangles_ = cut_exterior(m_, cut_, out_.positions, options_.delaunay);
    assemble(assign_patches());
    return std::move(out_);
  }

 private:
  std::uint32_t new_vertex(const glm::dvec3& p, std::int64_t origin, const Location* loc) {
    const std::uint32_t id = std::uint32_t(out_.positions.size());
    out_.positions.push_back(p);
    out_.vertex_origin.push_back(origin);
    cut_.location.push_back(loc ? *loc : Location{});
    cut_.on_b.push_back(loc ? 1 : 0);
    return id;
  }

  // S's vertices, the rim ones at their locations; a rim vertex on a B vertex takes its place.
  void add_s_vertices() {
    out_.s_vertex_count = std::uint32_t(s_.positions.size());
    b_owner_.assign(m_.positions.size(), kNone);
    for (std::uint32_t v = 0; v < s_.positions.size(); ++v) {
      const bool on_b = v < rim_.on_b.size() && rim_.on_b[v] && (s_.vertex_flags[v] & kVertexBoundary);
      if (!on_b) {
        new_vertex(glm::dvec3(glm::vec3(s_.positions[v])), v, nullptr);
        continue;
      }
      const Location& loc = rim_.at[v];
      new_vertex(loc.point, v, &loc);
      if (loc.kind == Location::kVertex) {
        if (b_owner_[loc.id] != kNone)
          throw RunError("internal: fracture surface vertices " + std::to_string(b_owner_[loc.id]) + " and " + std::to_string(v) +
                         " both lie on exterior vertex " + std::to_string(loc.id) + " at " + format_point(loc.point));
        b_owner_[loc.id] = v;
        ++out_.snapped_to_b_vertex;
      } else if (loc.kind == Location::kEdge) {
        cut_.edge_points[loc.id].emplace_back(loc.t, v);
      } else {
        cut_.face_points[loc.id].push_back(v);
      }
    }
  }

  void add_exterior_vertices() {
    cut_.b_vertex_gid.assign(m_.positions.size(), kNone);
    for (std::uint32_t b = 0; b < m_.positions.size(); ++b) {
      if (m_.vf_offsets[b] == m_.vf_offsets[b + 1]) continue;  // unused by B's triangles
      if (b_owner_[b] != kNone) {
        cut_.b_vertex_gid[b] = b_owner_[b];
        continue;
      }
      const Location loc = rim::vertex_location(m_, b);
      cut_.b_vertex_gid[b] = new_vertex(loc.point, -1 - std::int64_t(b), &loc);
    }
  }

  // Each rim edge, in the winding of its face, is a segment in one B triangle.
  void add_rim_segments() {
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e) {
      if (s_.edge_special[e] != kEdgeBoundary) continue;
      const std::uint32_t f = s_.ef_faces[s_.ef_offsets[e]];
      const glm::uvec4 face = s_.faces[f];
      int k = 0;
      while (!((face[k] == s_.edges[e].x || face[k] == s_.edges[e].y) &&
               (face[(k + 1) % 3] == s_.edges[e].x || face[(k + 1) % 3] == s_.edges[e].y)))
        ++k;
      const std::uint32_t p = face[k], q = face[(k + 1) % 3];
      cut_.segments.push_back({p, q, rim::common_face(m_, rim_.at[p], rim_.at[q])});
      mark_cut(p, q, f);
    }
  }

  // A patch face using (a, b) in the winding of S face f lies in f's front piece.
  void mark_cut(std::uint32_t a, std::uint32_t b, std::uint32_t f) {
    const glm::ivec2 pieces = s_.face_pieces[f];
    if (!cut_piece_.emplace(DirectedEdge{a, b}, pieces.x).second || !cut_piece_.emplace(DirectedEdge{b, a}, pieces.y).second)
      throw RunError("internal: fracture surface rim edge " + vertex_pair(a, b) + " is used twice");
  }

  // Flood fill of the cut B across edges that are not rim segments: per triangle, the lowest
  // triangle of its patch.
  std::vector<std::uint32_t> patch_roots() const {
    std::vector<std::array<std::uint32_t, 3>> keyed;  // (min, max, face)
    for (std::uint32_t t = 0; t < b_triangles_.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = b_triangles_[t][k], b = b_triangles_[t][(k + 1) % 3];
        keyed.push_back({std::min(a, b), std::max(a, b), t});
      }
    std::sort(keyed.begin(), keyed.end());
    std::vector<std::uint32_t> parent(b_triangles_.size());
    for (std::uint32_t t = 0; t < parent.size(); ++t) parent[t] = t;
    auto find = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (std::size_t i = 0; i < keyed.size(); i += 2) {
      const auto same = [&](std::size_t j) { return j < keyed.size() && keyed[j][0] == keyed[i][0] && keyed[j][1] == keyed[i][1]; };
      if (!same(i + 1) || same(i + 2))
        throw RunError("internal: the cut exterior is not closed at edge " + vertex_pair(keyed[i][0], keyed[i][1]));
      if (cut_piece_.count({keyed[i][0], keyed[i][1]})) continue;
      const std::uint32_t ra = find(keyed[i][2]), rb = find(keyed[i + 1][2]);
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
    for (std::uint32_t t = 0; t < parent.size(); ++t) parent[t] = find(t);
    return parent;
  }

  // Each patch's piece, from the cut edges around it (which must agree).
  std::vector<int> assign_patches() const {
    const std::vector<std::uint32_t> root = patch_roots();
    std::map<std::uint32_t, int> patch_piece;
    for (std::uint32_t t = 0; t < b_triangles_.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        auto it = cut_piece_.find({b_triangles_[t][k], b_triangles_[t][(k + 1) % 3]});
        if (it == cut_piece_.end()) continue;
        auto [at, inserted] = patch_piece.emplace(root[t], it->second);
        if (!inserted && at->second != it->second)
          throw RunError("the part of the exterior around " + format_point(out_.positions[b_triangles_[root[t]][0]]) +
                         " borders pieces " + std::to_string(at->second) + " and " + std::to_string(it->second) +
                         " along the cut: the fracture surface does not split the exterior consistently");
      }
    std::vector<int> piece(b_triangles_.size());
    for (std::uint32_t t = 0; t < b_triangles_.size(); ++t) {
      auto it = patch_piece.find(root[t]);
      if (it == patch_piece.end()) it = patch_piece.emplace(root[t], untouched_piece(b_triangles_[root[t]])).first;
      piece[t] = it->second;
    }
    return piece;
  }

  // A B component the rim does not touch lies in the piece on the side of the nearest S face.
  int untouched_piece(const Tri& t) const {
    const glm::dvec3 x = (out_.positions[t[0]] + out_.positions[t[1]] + out_.positions[t[2]]) / 3.0;
    double best = std::numeric_limits<double>::infinity();
    int piece = 0;
    for (std::uint32_t f = 0; f < s_.faces.size(); ++f) {
      const glm::dvec3 a = out_.positions[s_.faces[f].x], b = out_.positions[s_.faces[f].y], c = out_.positions[s_.faces[f].z];
      const ClosestPoint cp = closest_point_on_triangle(x, a, b, c);
      if (!(cp.squared_distance < best)) continue;
      best = cp.squared_distance;
      piece = glm::dot(x - cp.point, glm::cross(b - a, c - a)) >= 0.0 ? s_.face_pieces[f].x : s_.face_pieces[f].y;
    }
    return piece;
  }

  void assemble(const std::vector<int>& b_piece) {
    out_.pieces.resize(std::size_t(std::max(s_.piece_count, 1)));
    for (std::uint32_t f = 0; f < s_.faces.size(); ++f) {
      PieceSet::Piece& front = out_.pieces[std::size_t(s_.face_pieces[f].x)];
      PieceSet::Piece& back = out_.pieces[std::size_t(s_.face_pieces[f].y)];
      const Tri t{s_.faces[f].x, s_.faces[f].y, s_.faces[f].z};
      back.triangles.push_back(t);
      back.inside.push_back(1);
      front.triangles.push_back({t[0], t[2], t[1]});
      front.inside.push_back(1);
    }
    for (std::uint32_t t = 0; t < b_triangles_.size(); ++t) {
      PieceSet::Piece& piece = out_.pieces[std::size_t(b_piece[t])];
      piece.triangles.push_back(b_triangles_[t]);
      piece.inside.push_back(0);
    }
  }

  const ExteriorMesh& m_;
  const rim::RimOnB& rim_;
  PieceOptions options_;
  FractureSurface s_;
  PieceSet out_;
  ExteriorCut cut_;
  std::vector<std::uint32_t> b_owner_;  // per B vertex: the S vertex on it
  std::map<DirectedEdge, int> cut_piece_;  // directed rim segment -> piece of the patch face using it
  std::vector<Tri> b_triangles_;
};

}  // namespace

PieceSet build_pieces(const FractureSurface& s, const rim::ExteriorMesh& exterior, const rim::RimOnB& rim,
                      const PieceOptions& options) {
  return PieceBuilder(checked(s), exterior, rim, options).run();
}

PieceSet build_pieces(const FractureSurface& s, const MeshSoup& exterior, const PieceOptions& options) {
  const rim::ExteriorMesh m = rim::make_exterior_mesh(exterior);
  FractureSurface embedded = checked(s);
  const rim::Embedding e = rim::embed_rim(embedded, m, options.embed);
  PieceSet out = build_pieces(embedded, m, e.rim, options);
  out.rim_points_added = std::uint32_t(e.added.size());
  return out;
}

}  // namespace fracref
