// Split normals, box texture coordinates, and the piece OBJ files with normals.
#include "animate/piece_surface.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "animate/animate_internal.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using Tri = std::array<std::uint32_t, 3>;

glm::dvec3 unit_or(const glm::dvec3& v, const glm::dvec3& fallback) {
  const double l = glm::length(v);
  return l > 0.0 && std::isfinite(l) ? v / l : fallback;
}

// Per vertex, the area-weighted sum of the normals of its faces of `group`, and the first
// non-degenerate one as the fallback.
void accumulate(const std::vector<Tri>& faces, const std::vector<std::uint8_t>& inside, std::uint8_t group,
                const std::vector<glm::dvec3>& x, std::vector<glm::dvec3>& sum, std::vector<glm::dvec3>& first) {
  for (std::size_t t = 0; t < faces.size(); ++t) {
    if (inside[t] != group) continue;
    const Tri& f = faces[t];
    const glm::dvec3 n = glm::cross(x[f[1]] - x[f[0]], x[f[2]] - x[f[0]]);
    for (std::uint32_t v : f) {
      sum[v] += n;
      if (first[v] == glm::dvec3(0.0) && glm::length(n) > 0.0) first[v] = glm::normalize(n);
    }
  }
}

std::vector<glm::dvec3> group_normals(const std::vector<Tri>& faces, const std::vector<std::uint8_t>& inside, std::uint8_t group,
                                      const std::vector<glm::dvec3>& x) {
  std::vector<glm::dvec3> sum(x.size(), glm::dvec3(0.0)), first(x.size(), glm::dvec3(0.0));
  accumulate(faces, inside, group, x, sum, first);
  for (std::size_t v = 0; v < x.size(); ++v) sum[v] = unit_or(sum[v], unit_or(first[v], {0.0, 0.0, 1.0}));
  return sum;
}


// Shortest text that reads back to the same value: positions as doubles, normals as floats
// (a normal needs no more, and the piece files stay small).
template <class Real>
void append_number(std::string& out, Real value) {
  char buffer[32];
  out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

template <class Real>
void append_line(std::string& out, const char* head, const glm::dvec3& v) {
  out += head;
  for (int k = 0; k < 3; ++k) out += ' ', append_number(out, Real(v[k]));
  out += '\n';
}

// The piece on its own vertices, ascending shared index (write_pieces' order).
std::vector<Tri> local_triangles(const PieceSet::Piece& piece, std::vector<std::uint32_t>& used) {
  for (const Tri& t : piece.triangles) used.insert(used.end(), t.begin(), t.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<Tri> out;
  for (const Tri& t : piece.triangles) {
    Tri local;
    for (int k = 0; k < 3; ++k) local[k] = std::uint32_t(std::lower_bound(used.begin(), used.end(), t[k]) - used.begin());
    out.push_back(local);
  }
  return out;
}

void append_faces(std::string& out, const char* material, const std::vector<Tri>& split, const SplitPiece& s) {
  if (split.empty()) return;
  out += "usemtl ";
  out += material;
  out += '\n';
  for (const Tri& t : split) {
    out += 'f';
    for (std::uint32_t v : t) out += ' ' + std::to_string(s.original(v) + 1) + "//" + std::to_string(v + 1);
    out += '\n';
  }
}

std::string piece_obj_text(const PieceSet& set, const PieceSet::Piece& piece, const std::string& name) {
  std::vector<std::uint32_t> used;
  const std::vector<Tri> faces = local_triangles(piece, used);
  std::vector<glm::dvec3> x;
  for (std::uint32_t v : used) x.push_back(set.positions[v]);
  const SplitPiece s = split_piece(faces, piece.inside, x);
  std::string out = "# fracref " + name + "\nmtllib pieces.mtl\no " + name + "\n";
  for (const glm::dvec3& p : x) append_line<double>(out, "v", p);
  for (const glm::dvec3& n : s.normals) append_line<float>(out, "vn", n);
  append_faces(out, "outside", s.outside, s);
  append_faces(out, "inside", s.inside, s);
  return out;
}


}  // namespace

SplitPiece split_piece(const std::vector<Tri>& faces, const std::vector<std::uint8_t>& inside, const std::vector<glm::dvec3>& x) {
  SplitPiece s;
  s.vertex_count = x.size();
  std::vector<std::uint8_t> uses(x.size(), 0);  // bit 0: an outside face, bit 1: an inside one
  for (std::size_t t = 0; t < faces.size(); ++t)
    for (std::uint32_t v : faces[t]) uses[v] |= inside[t] ? 2 : 1;
  std::vector<std::uint32_t> copy(x.size(), UINT32_MAX);
  for (std::uint32_t v = 0; v < x.size(); ++v)
    if (uses[v] == 3) copy[v] = std::uint32_t(x.size() + s.rim.size()), s.rim.push_back(v);
  for (std::size_t t = 0; t < faces.size(); ++t) {
    Tri f = faces[t];
    if (inside[t])
      for (std::uint32_t& v : f) v = copy[v] == UINT32_MAX ? v : copy[v];
    (inside[t] ? s.inside : s.outside).push_back(f);
  }
  const std::vector<glm::dvec3> out_n = group_normals(faces, inside, 0, x), in_n = group_normals(faces, inside, 1, x);
  for (std::uint32_t v = 0; v < x.size(); ++v) s.normals.push_back(uses[v] & 1 ? out_n[v] : in_n[v]);
  for (std::uint32_t v : s.rim) s.normals.push_back(in_n[v]);
  return s;
}

glm::dvec2 box_texcoord(const glm::dvec3& material, const glm::dvec3& normal, const glm::dvec3& lo, double scale) {
  const glm::dvec3 a = glm::abs(normal), m = (material - lo) / scale;
  if (a.x >= a.y && a.x >= a.z) return {m.y, m.z};
  if (a.y >= a.z) return {m.z, m.x};
  return {m.x, m.y};
}

void write_piece_objs(const PieceSet& pieces, const std::filesystem::path& folder) {
  for_each_piece_file(pieces, folder, [&](const std::filesystem::path& dir, std::size_t p, const PieceSet::Piece& piece) {
    write_file_atomic(dir / (piece_name(p) + ".obj"), piece_obj_text(pieces, piece, piece_name(p)));
  });
  const std::filesystem::path dir = folder / "pieces";
  write_file_atomic(dir / "pieces.mtl", animate_detail::material_library("pieces"));
}

}  // namespace fracref
