// validate(): the invariants of the fracture surface, checked in a fixed order so that the first
// broken one is reported with the indices a user needs to find it.
#include <algorithm>
#include <cmath>
#include <future>
#include <initializer_list>
#include <sstream>

#include "surface/surface_internal.hpp"

namespace fracref {
namespace {

std::string str(std::size_t x) { return std::to_string(x); }
std::string count_text(std::size_t n, const std::string& noun) { return str(n) + " " + noun + (n == 1 ? "" : "s"); }
std::string edge_text(glm::uvec2 e) { return str(e.x) + "-" + str(e.y); }
std::string side_text(std::uint32_t side) { return "face " + str(side / 2) + ((side & 1u) ? " back" : " front"); }
bool uses(const glm::uvec4& f, std::uint32_t v) { return f.x == v || f.y == v || f.z == v; }
bool has_edge(const glm::uvec4& f, glm::uvec2 e) { return uses(f, e.x) && uses(f, e.y); }

std::string check_primary_sizes(const FractureSurface& s) {
  if (s.face_pieces.size() != s.faces.size())
    return "face_pieces has " + str(s.face_pieces.size()) + " entries, expected " + str(s.faces.size()) +
           " (one per face)";
  if (s.vertex_flags.size() != s.positions.size())
    return "vertex_flags has " + str(s.vertex_flags.size()) + " entries, expected " + str(s.positions.size()) +
           " (one per vertex)";
  if (s.piece_count < 0) return "piece_count is " + std::to_string(s.piece_count);
  return "";
}

std::string check_vertices(const FractureSurface& s) {
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    const glm::vec4& p = s.positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      std::ostringstream out;
      out << "vertex " << v << ": position (" << p.x << ", " << p.y << ", " << p.z << ") is not finite";
      return out.str();
    }
    if (p.w != 1.0f) {
      std::ostringstream out;
      out << "vertex " << v << ": position w is " << p.w << ", expected 1";
      return out.str();
    }
    if (s.vertex_flags[v] & ~kVertexFlagMask)
      return "vertex " + str(v) + ": unknown flag bits " + std::to_string(s.vertex_flags[v] & ~kVertexFlagMask);
  }
  return "";
}

std::string check_face(const FractureSurface& s, std::size_t f) {
  const glm::uvec4& t = s.faces[f];
  const glm::ivec2 p = s.face_pieces[f];
  auto at = [&] { return "face " + str(f) + ": "; };
  for (int i = 0; i < 3; ++i)
    if (t[i] >= s.positions.size())
      return at() + "vertex " + str(t[i]) + " out of range (" + str(s.positions.size()) + " vertices)";
  if (t.x == t.y || t.y == t.z || t.z == t.x)
    return at() + "repeats a vertex (" + str(t.x) + " " + str(t.y) + " " + str(t.z) + ")";
  if (t.w != 0) return at() + "w is " + str(t.w) + ", expected 0";
  for (int side = 0; side < 2; ++side)
    if (p[side] < 0 || p[side] >= s.piece_count)
      return at() + (side ? "back" : "front") + " piece " + std::to_string(p[side]) + " out of range (" +
             std::to_string(s.piece_count) + " pieces)";
  if (p.x == p.y) return at() + "front and back are the same piece " + std::to_string(p.x);
  return "";
}

// Each face alone (indices in range, which every later check reads through); the duplicates
// are checked after it (check_duplicate_faces).
std::string check_faces(const FractureSurface& s) {
  for (std::size_t f = 0; f < s.faces.size(); ++f)
    if (std::string m = check_face(s, f); !m.empty()) return m;
  return "";
}

std::string check_duplicate_faces(const FractureSurface& s) { return surface_detail::first_duplicate_face(s.faces); }

// A CSR whose offsets cannot be followed safely is reported before anything reads through it.
std::string check_csr(const std::string& name, const std::vector<std::uint32_t>& offsets, std::size_t rows,
                      const std::string& rows_name, const std::string& values_name, std::size_t values) {
  if (offsets.size() != rows + 1)
    return name + " has " + str(offsets.size()) + " entries, expected " + str(rows + 1) + " (" + rows_name + " + 1)";
  if (offsets[0] != 0) return name + " starts at " + str(offsets[0]) + ", expected 0";
  for (std::size_t k = 1; k < offsets.size(); ++k)
    if (offsets[k] < offsets[k - 1])
      return name + ": entry " + str(k) + " (" + str(offsets[k]) + ") is below entry " + str(k - 1) + " (" +
             str(offsets[k - 1]) + ")";
  if (offsets.back() != values)
    return name + " ends at " + str(offsets.back()) + " but " + values_name + " has " + str(values) + " entries";
  return "";
}

std::string check_size(const std::string& name, std::size_t have, std::size_t want, const std::string& why) {
  return have == want ? "" : name + " has " + str(have) + " entries, expected " + str(want) + " (" + why + ")";
}

std::string check_derived_shapes(const FractureSurface& s) {
  const std::size_t nv = s.positions.size(), nf = s.faces.size();
  const std::string checks[] = {
      check_csr("vf_offsets", s.vf_offsets, nv, "vertices", "vf_faces", s.vf_faces.size()),
      check_csr("ef_offsets", s.ef_offsets, s.edges.size(), "edges", "ef_faces", s.ef_faces.size()),
      check_size("face_edges", s.face_edges.size(), 3 * nf, "3 per face"),
      check_size("edge_special", s.edge_special.size(), s.edges.size(), "one per edge"),
      check_size("side_component", s.side_component.size(), 2 * nf, "2 per face"),
      check_csr("copy_offsets", s.copy_offsets, nv, "vertices", "copies", s.copies.size()),
      check_size("piece_vertex_counts", s.piece_vertex_counts.size(), std::size_t(s.piece_count), "one per piece"),
  };
  for (const std::string& m : checks)
    if (!m.empty()) return m;
  return "";
}

std::string check_vf(const FractureSurface& s, const FractureSurface& fresh) {
  for (std::uint32_t v = 0; v < s.positions.size(); ++v) {
    auto at = [&] { return "vertex " + str(v) + ": "; };
    for (std::uint32_t k = s.vf_offsets[v]; k < s.vf_offsets[v + 1]; ++k) {
      const std::uint32_t f = s.vf_faces[k];
      if (f >= s.faces.size()) return at() + "vf lists face " + str(f) + ", out of range (" + str(s.faces.size()) + " faces)";
      if (!uses(s.faces[f], v)) return at() + "vf lists face " + str(f) + " but face " + str(f) + " does not use vertex " + str(v);
      if (k > s.vf_offsets[v] && f <= s.vf_faces[k - 1])
        return at() + "vf faces not ascending (" + str(f) + " after " + str(s.vf_faces[k - 1]) + ")";
    }
    const auto b = s.vf_faces.begin() + s.vf_offsets[v], e = s.vf_faces.begin() + s.vf_offsets[v + 1];
    for (std::uint32_t k = fresh.vf_offsets[v]; k < fresh.vf_offsets[v + 1]; ++k)
      if (!std::binary_search(b, e, fresh.vf_faces[k]))
        return at() + "face " + str(fresh.vf_faces[k]) + " uses it but is missing from vf";
  }
  return "";
}

std::string check_edge_list(const FractureSurface& s, const FractureSurface& fresh) {
  for (std::size_t e = 0; e < std::min(s.edges.size(), fresh.edges.size()); ++e)
    if (s.edges[e] != fresh.edges[e])
      return "edges: entry " + str(e) + " is " + edge_text(s.edges[e]) + ", expected " + edge_text(fresh.edges[e]);
  if (s.edges.size() != fresh.edges.size())
    return "edges has " + str(s.edges.size()) + " entries, expected " + str(fresh.edges.size());
  return "";
}

// \pre stored edges equal the fresh ones, so both CSRs have the same rows.
std::string check_ef(const FractureSurface& s, const FractureSurface& fresh) {
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    auto at = [&] { return "edge " + edge_text(s.edges[e]) + ": "; };
    for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k) {
      const std::uint32_t f = s.ef_faces[k];
      if (f >= s.faces.size()) return at() + "ef lists face " + str(f) + ", out of range (" + str(s.faces.size()) + " faces)";
      if (!has_edge(s.faces[f], s.edges[e])) return at() + "ef lists face " + str(f) + " but face " + str(f) + " has no such edge";
      if (k > s.ef_offsets[e] && f <= s.ef_faces[k - 1])
        return at() + "ef faces not ascending (" + str(f) + " after " + str(s.ef_faces[k - 1]) + ")";
    }
    const auto b = s.ef_faces.begin() + s.ef_offsets[e], end = s.ef_faces.begin() + s.ef_offsets[e + 1];
    for (std::uint32_t k = fresh.ef_offsets[e]; k < fresh.ef_offsets[e + 1]; ++k)
      if (!std::binary_search(b, end, fresh.ef_faces[k]))
        return at() + "face " + str(fresh.ef_faces[k]) + " has it but is missing from ef";
  }
  return "";
}

std::string check_face_edges(const FractureSurface& s, const FractureSurface& fresh) {
  for (std::size_t k = 0; k < s.face_edges.size(); ++k)
    if (s.face_edges[k] != fresh.face_edges[k])
      return "face " + str(k / 3) + ": face_edges[" + str(k % 3) + "] is " + str(s.face_edges[k]) + ", expected " +
             str(fresh.face_edges[k]) + " (edge " + edge_text(fresh.edges[fresh.face_edges[k]]) + ")";
  return "";
}

const char* kind_name(std::uint8_t kind) {
  return kind == kEdgeRegular ? "regular" : kind == kEdgeBoundary ? "boundary" : kind == kEdgeNonManifold ? "non-manifold" : "unknown";
}

std::string check_edge_special(const FractureSurface& s, const FractureSurface& fresh) {
  for (std::size_t e = 0; e < s.edges.size(); ++e)
    if (s.edge_special[e] != fresh.edge_special[e])
      return "edge " + edge_text(s.edges[e]) + ": marked " + kind_name(s.edge_special[e]) + ", expected " +
             kind_name(fresh.edge_special[e]) + " (" + count_text(fresh.ef_offsets[e + 1] - fresh.ef_offsets[e], "face") + ")";
  return "";
}

// The lowest edge of kind `kind` at vertex v, or kNoEdge.
std::uint32_t first_edge_of_kind(const FractureSurface& s, std::uint32_t v, std::uint8_t kind) {
  std::uint32_t best = kNoEdge;
  for (std::uint32_t k = s.vf_offsets[v]; k < s.vf_offsets[v + 1]; ++k)
    for (std::uint32_t i = 0; i < 3; ++i) {
      const std::uint32_t e = s.face_edges[3 * s.vf_faces[k] + i];
      if (s.edge_special[e] == kind && (s.edges[e].x == v || s.edges[e].y == v)) best = std::min(best, e);
    }
  return best;
}

std::string check_flag_bit(const FractureSurface& fresh, std::uint32_t v, std::uint32_t stored, std::uint32_t bit) {
  auto at = [&] { return "vertex " + str(v) + ": "; };
  const bool boundary = bit == kVertexBoundary;
  const std::uint32_t e = first_edge_of_kind(fresh, v, boundary ? kEdgeBoundary : kEdgeNonManifold);
  if (boundary)
    return (stored & bit) ? at() + "flagged boundary but on no boundary edge"
                          : at() + "on boundary edge " + edge_text(fresh.edges[e]) + " but not flagged boundary";
  if (stored & bit) return at() + "flagged non-manifold but on no non-manifold edge and not a pinch vertex";
  if (e != kNoEdge) return at() + "on non-manifold edge " + edge_text(fresh.edges[e]) + " but not flagged non-manifold";
  std::vector<glm::uvec2> scratch;
  return at() + "pinch vertex (its faces form " + str(surface_detail::fan_count(fresh, v, scratch)) +
         " fans) but not flagged non-manifold";
}

std::string check_flags(const FractureSurface& s, const FractureSurface& fresh) {
  for (std::uint32_t v = 0; v < s.positions.size(); ++v)
    for (std::uint32_t bit : {kVertexBoundary, kVertexNonManifold})
      if ((s.vertex_flags[v] & bit) != (fresh.vertex_flags[v] & bit)) return check_flag_bit(fresh, v, s.vertex_flags[v], bit);
  return "";
}

std::string check_components(const FractureSurface& s, const FractureSurface& fresh) {
  if (s.component_count != fresh.component_count)
    return "component_count is " + str(s.component_count) + ", expected " + str(fresh.component_count);
  for (std::uint32_t side = 0; side < s.side_component.size(); ++side)
    if (s.side_component[side] != fresh.side_component[side])
      return side_text(side) + " side: component " + str(s.side_component[side]) + ", expected " +
             str(fresh.side_component[side]);
  return "";
}

std::string copies_text(const FractureSurface& s, std::uint32_t v) {
  std::string out = "(";
  for (std::uint32_t k = s.copy_offsets[v]; k < s.copy_offsets[v + 1]; ++k) {
    if (k > s.copy_offsets[v]) out += ' ';
    out += str(s.copies[k].x);
    out += ':';
    out += str(s.copies[k].y);
  }
  return out + ")";
}

std::string check_copies(const FractureSurface& s, const FractureSurface& fresh) {
  for (std::uint32_t v = 0; v < s.positions.size(); ++v) {
    const auto b = s.copies.begin() + s.copy_offsets[v], e = s.copies.begin() + s.copy_offsets[v + 1];
    const auto fb = fresh.copies.begin() + fresh.copy_offsets[v], fe = fresh.copies.begin() + fresh.copy_offsets[v + 1];
    if (!std::equal(b, e, fb, fe))
      return "vertex " + str(v) + ": copies (piece:local) " + copies_text(s, v) + ", expected " + copies_text(fresh, v);
  }
  for (std::size_t p = 0; p < s.piece_vertex_counts.size(); ++p)
    if (s.piece_vertex_counts[p] != fresh.piece_vertex_counts[p])
      return "piece " + str(p) + ": piece_vertex_counts is " + str(s.piece_vertex_counts[p]) + ", expected " +
             str(fresh.piece_vertex_counts[p]);
  return "";
}

// A component is one region of the volume, so all of its sides must name the same piece; the
// first join of two differently labelled sides says where the labels go wrong.
std::string check_component_pieces(const FractureSurface& s) {
  for (const surface_detail::SideJoin& j : surface_detail::side_joins(s)) {
    const int pa = side_piece(s, j.a), pb = side_piece(s, j.b);
    if (pa != pb)
      return "side component " + str(s.side_component[j.a]) + " holds pieces " + std::to_string(std::min(pa, pb)) +
             " and " + std::to_string(std::max(pa, pb)) + ": edge " + edge_text(s.edges[j.edge]) + " joins " +
             side_text(j.a) + " (piece " + std::to_string(pa) + ") and " + side_text(j.b) + " (piece " +
             std::to_string(pb) + ")";
  }
  return "";
}

// Each piece's outward faces must close up at every edge: none, a consistently wound pair, or one
// face on the exterior boundary.
std::string piece_edge_problem(const FractureSurface& s, std::uint32_t e, std::vector<std::pair<int, bool>>& uses_here) {
  uses_here.clear();  // (piece, outward face runs a -> b)
  for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k) {
    const std::uint32_t f = s.ef_faces[k];
    const bool forward = traverses_forward(s, f, e);
    uses_here.emplace_back(s.face_pieces[f].x, !forward);
    uses_here.emplace_back(s.face_pieces[f].y, forward);
  }
  std::sort(uses_here.begin(), uses_here.end());
  for (std::size_t k = 0; k < uses_here.size();) {
    const int p = uses_here[k].first;
    int count[2] = {0, 0};
    for (; k < uses_here.size() && uses_here[k].first == p; ++k) ++count[uses_here[k].second];
    auto at = [&] { return "piece " + std::to_string(p) + ": edge " + edge_text(s.edges[e]); };
    if (count[0] >= 2 || count[1] >= 2) return at() + " used by its outward faces in the same direction twice";
    if (count[0] + count[1] == 1 && s.edge_special[e] != kEdgeBoundary)
      return at() + " has a single outward face but is not a boundary edge";
  }
  return "";
}

std::string check_piece_edges(const FractureSurface& s) {
  std::vector<std::pair<int, bool>> scratch;
  for (std::uint32_t e = 0; e < s.edges.size(); ++e)
    if (std::string m = piece_edge_problem(s, e, scratch); !m.empty()) return m;
  return "";
}

std::string check_derived(const FractureSurface& s) {
  if (std::string m = check_derived_shapes(s); !m.empty()) return m;
  FractureSurface fresh = primary_copy(s);
  rebuild_adjacency(fresh);
  using Check = std::string (*)(const FractureSurface&, const FractureSurface&);
  for (Check check : {check_vf, check_edge_list, check_ef, check_face_edges, check_edge_special, check_flags,
                      check_components, check_copies})
    if (std::string m = check(s, fresh); !m.empty()) return m;
  return "";
}

}  // namespace

namespace {

using Check = std::string (*)(const FractureSurface&);

// Below this many faces the checks after the faces' run on one thread.
constexpr std::size_t kParallelFaces = 8192;

std::string first_of(const FractureSurface& s, std::initializer_list<Check> checks) {
  for (Check check : checks)
    if (std::string m = check(s); !m.empty()) return m;
  return "";
}

// The invariants in validate()'s order; `derived` checks the derived arrays. Once every face's
// indices are known to be in range, the search for duplicate faces (a sort of all of them) runs
// beside the checks that follow it, and once the derived arrays are known to be sound, the
// components' pieces are checked beside the pieces' edges; the messages still come in order.
std::string first_problem(const FractureSurface& s, Check derived) {
  if (std::string m = first_of(s, {check_primary_sizes, check_vertices, check_faces}); !m.empty()) return m;
  if (s.faces.size() < kParallelFaces)
    return first_of(s, {check_duplicate_faces, derived, check_component_pieces, check_piece_edges});
  auto duplicates = std::async(std::launch::async, [&s] { return check_duplicate_faces(s); });
  std::string rest = derived(s);
  if (rest.empty()) {
    auto components = std::async(std::launch::async, [&s] { return check_component_pieces(s); });
    std::string edges = check_piece_edges(s);
    rest = components.get();
    if (rest.empty()) rest = std::move(edges);
  }
  std::string m = duplicates.get();
  return m.empty() ? rest : m;
}

}  // namespace

std::string validate(const FractureSurface& s) { return first_problem(s, check_derived); }

std::string validate_rebuilt(const FractureSurface& s) { return first_problem(s, check_derived_shapes); }

std::string validate_edges(const FractureSurface& s, std::span<const std::uint32_t> edges) {
  std::vector<std::pair<int, bool>> scratch;
  std::vector<surface_detail::SideJoin> joins;
  for (const std::uint32_t e : edges) {
    if (std::string m = piece_edge_problem(s, e, scratch); !m.empty()) return m;
    joins.clear();
    surface_detail::side_joins_at(s, e, joins);
    for (const surface_detail::SideJoin& j : joins)
      if (side_piece(s, j.a) != side_piece(s, j.b))
        return "edge " + edge_text(s.edges[e]) + " joins " + side_text(j.a) + " (piece " +
               std::to_string(side_piece(s, j.a)) + ") and " + side_text(j.b) + " (piece " +
               std::to_string(side_piece(s, j.b)) + ")";
  }
  return "";
}

}  // namespace fracref
