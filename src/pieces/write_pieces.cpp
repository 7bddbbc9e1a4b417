// write_pieces: one PLY and one OBJ per piece, and the OBJ materials.
#include <algorithm>
#include <charconv>
#include <cstdio>

#include "io/mesh_io.hpp"
#include "pieces/pieces.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using Tri = std::array<std::uint32_t, 3>;

constexpr const char* kMaterialFile = "pieces.mtl";

std::string piece_name(std::size_t p) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "piece_%03zu", p);
  return buffer;
}

// Shortest text that reads back to the same double (std::to_chars, locale-free).
void append_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

// The piece on its own vertices, in ascending shared index.
MeshSoup piece_soup(const PieceSet& set, const PieceSet::Piece& piece) {
  std::vector<std::uint32_t> used;
  for (const Tri& t : piece.triangles) used.insert(used.end(), t.begin(), t.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  MeshSoup soup;
  for (std::uint32_t v : used) soup.positions.push_back(set.positions[v]);
  for (const Tri& t : piece.triangles) {
    std::array<std::uint32_t, 3> local;
    for (int k = 0; k < 3; ++k) local[k] = std::uint32_t(std::lower_bound(used.begin(), used.end(), t[k]) - used.begin());
    soup.triangles.push_back(local);
  }
  soup.polygons = soup.triangles.size();
  for (std::uint32_t i = 0; i < soup.triangles.size(); ++i) soup.triangle_polygon.push_back(i);
  const char* axes[3] = {"mx", "my", "mz"};
  for (int a = 0; a < 3; ++a) {
    PropertyColumn column{axes[a], PropertyType::Float64, {}};
    for (const glm::dvec3& p : soup.positions) column.values.push_back(p[a]);
    soup.vertex_properties.push_back(std::move(column));
  }
  PropertyColumn inside{"inside", PropertyType::UInt8, {}};
  for (std::uint8_t flag : piece.inside) inside.values.push_back(flag);
  soup.face_properties.push_back(std::move(inside));
  return soup;
}

std::string obj_text(const MeshSoup& soup, const std::vector<std::uint8_t>& inside, const std::string& name) {
  std::string out = "# fracref " + name + "\nmtllib " + kMaterialFile + "\no " + name + "\n";
  for (const glm::dvec3& p : soup.positions) {
    out += "v ";
    append_number(out, p.x);
    out += ' ';
    append_number(out, p.y);
    out += ' ';
    append_number(out, p.z);
    out += '\n';
  }
  for (std::uint8_t group : {std::uint8_t(0), std::uint8_t(1)}) {
    if (std::find(inside.begin(), inside.end(), group) == inside.end()) continue;
    out += group ? "usemtl inside\n" : "usemtl outside\n";
    for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
      if (inside[t] != group) continue;
      const auto& tri = soup.triangles[t];
      out += "f " + std::to_string(tri[0] + 1) + ' ' + std::to_string(tri[1] + 1) + ' ' + std::to_string(tri[2] + 1) + '\n';
    }
  }
  return out;
}

const char* material_text() {
  return "# fracref pieces: exterior (outside) and fracture (inside) faces\n"
         "newmtl outside\nKa 0 0 0\nKd 0.8 0.8 0.8\nKs 0.1 0.1 0.1\nNs 20\nillum 2\n\n"
         "newmtl inside\nKa 0 0 0\nKd 0.85 0.55 0.35\nKs 0.05 0.05 0.05\nNs 10\nillum 2\n";
}

}  // namespace

void write_pieces(const PieceSet& pieces, const std::filesystem::path& folder, const PieceWriteOptions& options) {
  const std::filesystem::path dir = folder / "pieces";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw RunError(dir.string() + ": cannot create the folder: " + ec.message());
  for (std::size_t p = 0; p < pieces.pieces.size(); ++p) {
    const PieceSet::Piece& piece = pieces.pieces[p];
    if (piece.inside.size() != piece.triangles.size())
      throw RunError(piece_name(p) + ": " + std::to_string(piece.inside.size()) + " inside flags for " +
                     std::to_string(piece.triangles.size()) + " triangles");
    const MeshSoup soup = piece_soup(pieces, piece);
    if (options.ply) {
      MeshWriteOptions write;
      write.ply_binary = options.ply_binary;
      write_mesh(dir / (piece_name(p) + ".ply"), soup, write);
    }
    if (options.obj) write_file_atomic(dir / (piece_name(p) + ".obj"), obj_text(soup, piece.inside, piece_name(p)));
  }
  if (options.obj) write_file_atomic(dir / kMaterialFile, material_text());
}

}  // namespace fracref
