// Strict reader of TetGen .node + .ele files, and of crack lists.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include "coarse/coarse_internal.hpp"
#include "coarse/tet_readers.hpp"

namespace fracref {
namespace {
using namespace coarse_detail;
namespace fs = std::filesystem;

struct NodeFile {
  std::vector<glm::dvec3> points;
  std::int64_t base = 0;  // 0 or 1: the first index
};

// Checks the running index of entry i (consecutive from the first one, which must be 0 or 1).
std::int64_t check_index(const TokenLines& in, std::size_t i, std::int64_t base, const char* what) {
  const std::int64_t index = in.integer(in.tokens()[0], std::string(what) + " index");
  if (i == 0) {
    if (index != 0 && index != 1)
      throw in.error(std::string("the first ") + what + " index is " + std::to_string(index) + "; TetGen numbers from 0 or 1");
    return index;
  }
  if (index != base + std::int64_t(i))
    throw in.error(std::string(what) + " index " + std::to_string(index) + " breaks the sequence (expected " +
                   std::to_string(base + std::int64_t(i)) + ")");
  return base;
}

void end_of_data(TokenLines& in, std::size_t count, const char* what) {
  if (in.next())
    throw in.error("data after the " + std::to_string(count) + " " + what + " announced in the header");
}

NodeFile read_node(const fs::path& path) {
  const std::string text = io_detail::read_whole_file(path);
  TokenLines in(path.string(), text);
  if (!in.next()) throw in.error("file has no header line (only comments or blank lines)");
  if (in.tokens().size() != 4)
    throw in.error("header needs 4 values (points dimension attributes markers), got " + std::to_string(in.tokens().size()));
  const std::size_t count = in.count(in.tokens()[0], "point count");
  const std::int64_t dim = in.integer(in.tokens()[1], "dimension");
  const std::size_t attributes = in.count(in.tokens()[2], "attribute count");
  const std::int64_t markers = in.integer(in.tokens()[3], "boundary marker count");
  if (count == 0) throw in.error("the file has 0 points (points in a .poly file are not supported)");
  if (dim != 3) throw in.error("dimension " + std::to_string(dim) + " is not supported (only 3)");
  if (markers != 0 && markers != 1) throw in.error("boundary marker count " + std::to_string(markers) + " is not 0 or 1");
  if (attributes > 1000) throw in.error("attribute count " + std::to_string(attributes) + " is implausible");
  const std::size_t values = 4 + attributes + std::size_t(markers);
  NodeFile node;
  node.points.reserve(std::min<std::size_t>(count, text.size() / 8 + 1));
  for (std::size_t i = 0; i < count; ++i) {
    if (!in.next()) throw in.error("file ends after " + std::to_string(i) + " of the " + std::to_string(count) + " points");
    in.expect_tokens(values, "point", "index x y z, " + std::to_string(attributes) + " attributes, " +
                                          std::to_string(markers) + " marker");
    node.base = check_index(in, i, node.base, "point");
    const auto& t = in.tokens();
    node.points.emplace_back(in.real(t[1], "coordinate"), in.real(t[2], "coordinate"), in.real(t[3], "coordinate"));
    for (std::size_t k = 4; k < 4 + attributes; ++k) in.real(t[k], "attribute");
    if (markers) in.integer(t[values - 1], "boundary marker");
  }
  end_of_data(in, count, "points");
  return node;
}

std::int64_t region_label(const TokenLines& in, std::string_view token) {
  const double region = in.real(token, "region attribute");
  if (region < 0 || region != std::floor(region) || region > 9.0e15)
    throw in.error("region attribute " + quote(token) + " is not an integer >= 0 (it is the piece label)");
  return std::int64_t(region);
}

void read_ele(const fs::path& path, const NodeFile& node, TetMesh& mesh) {
  const std::string text = io_detail::read_whole_file(path);
  TokenLines in(path.string(), text);
  if (!in.next()) throw in.error("file has no header line (only comments or blank lines)");
  in.expect_tokens(3, "header", "tetrahedra nodes-per-tet attributes");
  const std::size_t count = in.count(in.tokens()[0], "tetrahedron count");
  const std::int64_t corners = in.integer(in.tokens()[1], "nodes per tetrahedron");
  const std::size_t attributes = in.count(in.tokens()[2], "attribute count");
  if (count == 0) throw in.error("the mesh has no tetrahedra");
  if (corners != 4) throw in.error(std::to_string(corners) + " nodes per tetrahedron are not supported (only 4)");
  if (attributes > 1) throw in.error(std::to_string(attributes) + " attributes per tetrahedron; expected 0 or 1 (the region = piece)");
  const std::size_t n = node.points.size();
  std::int64_t base = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!in.next()) throw in.error("file ends after " + std::to_string(i) + " of the " + std::to_string(count) + " tetrahedra");
    in.expect_tokens(5 + attributes, "tetrahedron", attributes ? "index n0 n1 n2 n3 region" : "index n0 n1 n2 n3");
    base = check_index(in, i, base, "tetrahedron");
    glm::uvec4 tet;
    for (int k = 0; k < 4; ++k) {
      const std::int64_t id = in.integer(in.tokens()[1 + k], "node index") - node.base;
      if (id < 0 || id >= std::int64_t(n))
        throw in.error("node index " + std::string(in.tokens()[1 + k]) + " is out of range (the .node file has " +
                       std::to_string(n) + " points numbered from " + std::to_string(node.base) + ")");
      tet[k] = std::uint32_t(id);
    }
    mesh.tets.push_back(tet);
    mesh.labels.push_back(attributes ? region_label(in, in.tokens()[5]) : 0);
    mesh.tet_lines.push_back(in.line());
  }
  end_of_data(in, count, "tetrahedra");
}

}  // namespace

TetMesh read_tetgen(const fs::path& path) {
  fs::path stem = path;
  const std::string ext = path.extension().string();
  if (ext == ".node" || ext == ".ele") stem.replace_extension();
  const fs::path node_path = fs::path(stem.string() + ".node"), ele_path = fs::path(stem.string() + ".ele");
  NodeFile node = read_node(node_path);
  TetMesh mesh;
  mesh.file = ele_path.string();
  read_ele(ele_path, node, mesh);
  mesh.vertices = std::move(node.points);
  return mesh;
}

CrackList read_cracks(const fs::path& path) {
  CrackList list;
  list.file = path.string();
  std::error_code ec;
  if (fs::is_regular_file(path, ec) && fs::file_size(path, ec) == 0 && !ec) return list;  // an empty list
  const std::string text = io_detail::read_whole_file(path);
  TokenLines in(list.file, text);
  while (in.next()) {
    in.expect_tokens(3, "crack face", "a b c: 0-based vertex ids");
    glm::uvec3 f;
    for (int k = 0; k < 3; ++k) {
      const std::int64_t id = in.integer(in.tokens()[k], "vertex id");
      if (id < 0 || id > std::int64_t(UINT32_MAX - 1)) throw in.error("vertex id " + std::to_string(id) + " is out of range");
      f[k] = std::uint32_t(id);
    }
    list.faces.push_back(f);
    list.lines.push_back(in.line());
  }
  return list;
}

}  // namespace fracref
