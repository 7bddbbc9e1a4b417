// write_pieces: one PLY per piece (the OBJs, with split normals, are written by animate).
#include <algorithm>
#include <cstdio>

#include "io/mesh_io.hpp"
#include "pieces/pieces.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using Tri = std::array<std::uint32_t, 3>;


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

}  // namespace

std::string piece_name(std::size_t p) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "piece_%03zu", p);
  return buffer;
}

void for_each_piece_file(const PieceSet& pieces, const std::filesystem::path& folder,
                         const std::function<void(const std::filesystem::path&, std::size_t, const PieceSet::Piece&)>& write) {
  const std::filesystem::path dir = folder / "pieces";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw RunError(dir.string() + ": cannot create the folder: " + ec.message());
  for (std::size_t p = 0; p < pieces.pieces.size(); ++p) {
    const PieceSet::Piece& piece = pieces.pieces[p];
    if (piece.inside.size() != piece.triangles.size())
      throw RunError(piece_name(p) + ": " + std::to_string(piece.inside.size()) + " inside flags for " +
                     std::to_string(piece.triangles.size()) + " triangles");
    write(dir, p, piece);
  }
}

void write_pieces(const PieceSet& pieces, const std::filesystem::path& folder, const PieceWriteOptions& options) {
  MeshWriteOptions write;
  write.ply_binary = options.ply_binary;
  for_each_piece_file(pieces, folder, [&](const std::filesystem::path& dir, std::size_t p, const PieceSet::Piece& piece) {
    write_mesh(dir / (piece_name(p) + ".ply"), piece_soup(pieces, piece), write);
  });
}

}  // namespace fracref
