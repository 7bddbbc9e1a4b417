// Building the fracture surface, its per-piece views, and lookups.
#include "surface/fracture_surface.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "surface/surface_internal.hpp"
#include "util/error.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {

constexpr std::size_t kParallelRebuildFaces = 8192;  // below this a thread costs more than it saves

std::string vec_text(const glm::vec4& p) {
  std::ostringstream out;
  out << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return out.str();
}

void check_input_vertices(const std::vector<glm::vec4>& positions) {
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const glm::vec4& p = positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError("vertex " + std::to_string(v) + ": position " + vec_text(p) + " is not finite");
  }
}

void check_input_face(std::size_t f, const glm::uvec4& face, const glm::ivec2& pieces, std::size_t nv,
                      int piece_count) {
  const std::string at = "face " + std::to_string(f) + ": ";
  for (int i = 0; i < 3; ++i)
    if (face[i] >= nv)
      throw InputError(at + "vertex " + std::to_string(face[i]) + " out of range (" + std::to_string(nv) +
                       " vertices)");
  if (face.x == face.y || face.y == face.z || face.z == face.x)
    throw InputError(at + "repeats a vertex (" + std::to_string(face.x) + " " + std::to_string(face.y) + " " +
                     std::to_string(face.z) + ")");
  for (int side = 0; side < 2; ++side)
    if (pieces[side] < 0 || pieces[side] >= piece_count)
      throw InputError(at + (side ? "back" : "front") + " piece " + std::to_string(pieces[side]) +
                       " out of range (" + std::to_string(piece_count) + " pieces)");
  if (pieces.x == pieces.y)
    throw InputError(at + "front and back are the same piece " + std::to_string(pieces.x));
}

// Sorted vertex triples with their face, to find faces on the same vertex set.
std::vector<std::pair<glm::uvec3, std::uint32_t>> sorted_vertex_sets(const std::vector<glm::uvec4>& faces) {
  std::vector<std::pair<glm::uvec3, std::uint32_t>> sets(faces.size());
  for (std::uint32_t f = 0; f < faces.size(); ++f) {
    std::uint32_t v[3] = {faces[f].x, faces[f].y, faces[f].z};
    std::sort(v, v + 3);
    sets[f] = {glm::uvec3(v[0], v[1], v[2]), f};
  }
  std::sort(sets.begin(), sets.end(), [](const auto& x, const auto& y) {
    if (x.first.x != y.first.x) return x.first.x < y.first.x;
    if (x.first.y != y.first.y) return x.first.y < y.first.y;
    if (x.first.z != y.first.z) return x.first.z < y.first.z;
    return x.second < y.second;
  });
  return sets;
}

}  // namespace

namespace surface_detail {

std::string first_duplicate_face(const std::vector<glm::uvec4>& faces) {
  const auto sets = sorted_vertex_sets(faces);
  std::uint32_t best = kNoEdge, original = 0;
  for (std::size_t k = 1, first = 0; k < sets.size(); ++k) {
    if (sets[k].first != sets[k - 1].first) first = k;
    else if (sets[k].second < best) best = sets[k].second, original = sets[first].second;
  }
  if (best == kNoEdge) return "";
  const glm::uvec4& f = faces[best];
  return "face " + std::to_string(best) + ": duplicate of face " + std::to_string(original) + " (vertices " +
         std::to_string(f.x) + " " + std::to_string(f.y) + " " + std::to_string(f.z) + ")";
}

}  // namespace surface_detail

FractureSurface make_fracture_surface(std::vector<glm::vec4> positions, std::vector<glm::uvec4> faces,
                                      std::vector<glm::ivec2> face_pieces, int piece_count) {
  if (piece_count < 0) throw InputError("piece count " + std::to_string(piece_count) + " is negative");
  if (faces.size() != face_pieces.size())
    throw InputError("face_pieces has " + std::to_string(face_pieces.size()) + " entries, expected " +
                     std::to_string(faces.size()) + " (one per face)");
  check_input_vertices(positions);
  for (std::size_t f = 0; f < faces.size(); ++f)
    check_input_face(f, faces[f], face_pieces[f], positions.size(), piece_count);
  if (std::string dup = surface_detail::first_duplicate_face(faces); !dup.empty()) throw InputError(dup);
  FractureSurface s;
  for (glm::vec4& p : positions) p.w = 1.0f;
  for (glm::uvec4& f : faces) f.w = 0;
  s.positions = std::move(positions);
  s.faces = std::move(faces);
  s.face_pieces = std::move(face_pieces);
  s.piece_count = piece_count;
  s.vertex_flags.assign(s.positions.size(), kVertexOriginal);
  rebuild_adjacency(s);
  return s;
}

void rebuild_adjacency(FractureSurface& s) {
  const std::size_t nv = s.positions.size();
  if (s.face_pieces.size() != s.faces.size())
    throw RunError("rebuild_adjacency: " + std::to_string(s.faces.size()) + " faces but " +
                   std::to_string(s.face_pieces.size()) + " face piece pairs");
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    for (int i = 0; i < 3; ++i)
      if (s.faces[f][i] >= nv)
        throw RunError("rebuild_adjacency: face " + std::to_string(f) + ": vertex " +
                       std::to_string(s.faces[f][i]) + " out of range (" + std::to_string(nv) + " vertices)");
    for (int side = 0; side < 2; ++side)
      if (s.face_pieces[f][side] < 0 || s.face_pieces[f][side] >= s.piece_count)
        throw RunError("rebuild_adjacency: face " + std::to_string(f) + ": piece " +
                       std::to_string(s.face_pieces[f][side]) + " out of range (" +
                       std::to_string(s.piece_count) + " pieces)");
  }
  surface_detail::build_vertex_faces(s);
  surface_detail::build_edges(s);
  // The flags, the side components and the copies each read the tables above and write their
  // own: on a large surface two of them share a second thread (a fifth off each rebuild, which
  // the refiner makes twice an iteration).
  if (s.faces.size() < kParallelRebuildFaces) {
    surface_detail::build_vertex_flags(s);
    surface_detail::build_components(s);
    surface_detail::build_copies(s);
    return;
  }
  parallel_pair([&s] { surface_detail::build_vertex_flags(s); },
                [&s] {
                  surface_detail::build_components(s);
                  surface_detail::build_copies(s);
                });
}

FractureSurface primary_copy(const FractureSurface& s) {
  FractureSurface t;
  t.positions = s.positions;
  t.faces = s.faces;
  t.face_pieces = s.face_pieces;
  t.vertex_flags = s.vertex_flags;
  t.piece_count = s.piece_count;
  return t;
}

void rebuild_after_splits(FractureSurface& s, std::size_t first_vertex, std::size_t first_face,
                          std::span<const std::uint32_t> origin) {
  if (origin.size() != s.faces.size() - first_face)
    throw RunError("rebuild_after_splits: " + std::to_string(origin.size()) + " origins for " +
                   std::to_string(s.faces.size() - first_face) + " new faces");
  for (std::size_t k = 0; k < origin.size(); ++k)
    if (origin[k] >= first_face + k)
      throw RunError("rebuild_after_splits: face " + std::to_string(first_face + k) + " split off face " +
                     std::to_string(origin[k]) + ", not an older one");
  surface_detail::build_vertex_faces(s);
  surface_detail::build_edges(s);
  surface_detail::extend_after_splits(s, first_vertex, first_face, origin);
}

void rebuild_edge_table(FractureSurface& s) { surface_detail::build_edges(s); }

void rebuild_after_flips(FractureSurface& s) {
  surface_detail::build_vertex_faces(s);
  surface_detail::build_edges(s);
}

PieceMesh piece_mesh(const FractureSurface& s, int piece) {
  if (piece < 0 || piece >= s.piece_count)
    throw RunError("piece_mesh: piece " + std::to_string(piece) + " out of range (" +
                   std::to_string(s.piece_count) + " pieces)");
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> local(s.positions.size(), kNone);
  PieceMesh mesh;
  for (std::uint32_t f = 0; f < s.faces.size(); ++f)
    if (s.face_pieces[f].x == piece || s.face_pieces[f].y == piece) {
      mesh.face_to_canonical.push_back(f);
      for (int i = 0; i < 3; ++i) local[s.faces[f][i]] = 0;
    }
  for (std::uint32_t v = 0; v < local.size(); ++v)
    if (local[v] != kNone) {
      local[v] = std::uint32_t(mesh.vertex_to_canonical.size());
      mesh.vertex_to_canonical.push_back(v);
      mesh.positions.emplace_back(s.positions[v]);
    }
  for (std::uint32_t f : mesh.face_to_canonical) {
    const glm::uvec4& t = s.faces[f];
    // The normal points into the front piece, so the front piece sees the face reversed.
    if (s.face_pieces[f].y == piece) mesh.triangles.emplace_back(local[t.x], local[t.y], local[t.z]);
    else mesh.triangles.emplace_back(local[t.x], local[t.z], local[t.y]);
  }
  return mesh;
}

std::vector<glm::dvec3> double_positions(const FractureSurface& s) {
  std::vector<glm::dvec3> out;
  out.reserve(s.positions.size());
  for (const glm::vec4& p : s.positions) out.emplace_back(glm::vec3(p));
  return out;
}

std::vector<std::array<std::uint32_t, 3>> face_triangles(const FractureSurface& s) {
  std::vector<std::array<std::uint32_t, 3>> out;
  out.reserve(s.faces.size());
  for (const glm::uvec4& f : s.faces) out.push_back({f.x, f.y, f.z});
  return out;
}

std::uint32_t find_edge(const FractureSurface& s, std::uint32_t a, std::uint32_t b) {
  const glm::uvec2 key(std::min(a, b), std::max(a, b));
  auto less = [](glm::uvec2 x, glm::uvec2 y) { return x.x != y.x ? x.x < y.x : x.y < y.y; };
  auto it = std::lower_bound(s.edges.begin(), s.edges.end(), key, less);
  return it != s.edges.end() && *it == key ? std::uint32_t(it - s.edges.begin()) : kNoEdge;
}

std::vector<int> component_pieces(const FractureSurface& s) {
  constexpr int kUnset = -2;
  std::vector<int> pieces(s.component_count, kUnset);
  for (std::uint32_t side = 0; side < s.side_component.size(); ++side) {
    int& p = pieces[s.side_component[side]];
    const int here = side_piece(s, side);
    p = p == kUnset ? here : p == here ? p : -1;
  }
  return pieces;
}

void validate_or_throw(const FractureSurface& s) {
  if (std::string message = validate(s); !message.empty()) throw RunError(message);
}

}  // namespace fracref
