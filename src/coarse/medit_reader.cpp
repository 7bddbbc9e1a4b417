// Strict reader of MEDIT ASCII .mesh files (tetrahedra with piece references).
#include <algorithm>
#include <cctype>
#include <cstring>
#include <string>

#include "coarse/coarse_internal.hpp"
#include "coarse/tet_readers.hpp"

namespace fracref {
namespace {
using namespace coarse_detail;

// A section fracref reads only to check it: `values` tokens per entry, the first `vertex_ids` of
// them vertex ids, then `entity_ids` ids of other entities (>= 1); `reals` sections hold numbers.
struct IgnoredSection {
  const char* name;
  int values;
  int vertex_ids;
  int entity_ids;
  bool reals;
};

constexpr IgnoredSection kIgnored[] = {
    {"Triangles", 4, 3, 0, false},       {"Quadrilaterals", 5, 4, 0, false}, {"Edges", 3, 2, 0, false},
    {"Corners", 1, 1, 0, false},         {"RequiredVertices", 1, 1, 0, false}, {"Ridges", 1, 0, 1, false},
    {"RequiredEdges", 1, 0, 1, false},   {"RequiredTriangles", 1, 0, 1, false}, {"Normals", 3, 0, 0, true},
    {"Tangents", 3, 0, 0, true},         {"NormalAtVertices", 2, 1, 1, false}, {"TangentAtVertices", 2, 1, 1, false},
};

constexpr const char* kUnsupported[] = {"Hexahedra", "Prisms", "Pyramids", "TetrahedraP2", "TrianglesP2", "EdgesP2"};

bool same_word(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

bool looks_numeric(std::string_view token) {
  return !token.empty() && (std::isdigit(static_cast<unsigned char>(token[0])) || token[0] == '-' ||
                            token[0] == '+' || token[0] == '.');
}

class MeditParser {
 public:
  MeditParser(std::string file, std::string_view text) : in_(std::move(file), text) { mesh_.file = in_.file(); }
  TetMesh parse();

 private:
  std::int64_t keyword_value(const char* keyword);
  std::size_t section_count(const std::string& keyword);
  void next_entry(const std::string& section, std::size_t done, std::size_t count);
  std::uint32_t vertex_id(std::string_view token, const char* what) const;
  void section(std::string_view keyword);
  void vertices(std::size_t count);
  void tetrahedra(std::size_t count);
  void ignored(const IgnoredSection& shape, std::size_t count);
  void seen(const std::string& name);

  TokenLines in_;
  TetMesh mesh_;
  bool have_vertices_ = false;
  std::string previous_ = "the header";
  std::vector<std::string> sections_;
};

// The value of `keyword` on its own line or the next one.
std::int64_t MeditParser::keyword_value(const char* keyword) {
  if (!in_.next()) throw in_.error(std::string("file is empty or has no '") + keyword + "' line");
  if (!same_word(in_.tokens()[0], keyword))
    throw in_.error(std::string("expected '") + keyword + "', found " + quote(in_.tokens()[0]) +
                    (std::strcmp(keyword, "MeshVersionFormatted") == 0 ? " (not a MEDIT .mesh file?)" : ""));
  if (in_.tokens().size() > 2) throw in_.error(std::string("'") + keyword + "' takes one value");
  if (in_.tokens().size() == 2) return in_.integer(in_.tokens()[1], keyword);
  if (!in_.next()) throw in_.error(std::string("file ends before the value of '") + keyword + "'");
  in_.expect_tokens(1, std::string("'") + keyword + "'", "one integer");
  return in_.integer(in_.tokens()[0], keyword);
}

std::size_t MeditParser::section_count(const std::string& keyword) {
  if (in_.tokens().size() > 2) throw in_.error("section '" + keyword + "' line takes only its count");
  if (in_.tokens().size() == 2) return in_.count(in_.tokens()[1], keyword + " count");
  if (!in_.next()) throw in_.error("file ends before the count of section '" + keyword + "'");
  in_.expect_tokens(1, "the count of section '" + keyword + "'", "one integer");
  return in_.count(in_.tokens()[0], keyword + " count");
}

void MeditParser::next_entry(const std::string& section, std::size_t done, std::size_t count) {
  const std::string of = std::to_string(done) + " of the " + std::to_string(count) + " entries of section '" + section + "'";
  if (!in_.next()) throw in_.error("file ends after " + of);
  if (!looks_numeric(in_.tokens()[0]))
    throw in_.error("found " + quote(in_.tokens()[0]) + " after " + of + " (is the count too large?)");
}

std::uint32_t MeditParser::vertex_id(std::string_view token, const char* what) const {
  const std::int64_t id = in_.integer(token, what);
  const std::size_t n = mesh_.vertices.size();
  if (id < 1 || id > std::int64_t(n))
    throw in_.error(std::string(what) + " " + std::to_string(id) + " is out of range (the file has " + std::to_string(n) +
                    " vertices; MEDIT indices start at 1)");
  return std::uint32_t(id - 1);
}

void MeditParser::vertices(std::size_t count) {
  mesh_.vertices.reserve(std::min<std::size_t>(count, 1 << 24));
  for (std::size_t i = 0; i < count; ++i) {
    next_entry("Vertices", i, count);
    in_.expect_tokens(4, "vertex", "x y z ref");
    const auto& t = in_.tokens();
    glm::dvec3 p(in_.real(t[0], "coordinate"), in_.real(t[1], "coordinate"), in_.real(t[2], "coordinate"));
    in_.integer(t[3], "vertex reference");
    mesh_.vertices.push_back(p);
  }
  have_vertices_ = true;
}

void MeditParser::tetrahedra(std::size_t count) {
  mesh_.tets.reserve(std::min<std::size_t>(count, 1 << 24));
  for (std::size_t i = 0; i < count; ++i) {
    next_entry("Tetrahedra", i, count);
    in_.expect_tokens(5, "tetrahedron", "a b c d ref");
    const auto& t = in_.tokens();
    glm::uvec4 tet;
    for (int k = 0; k < 4; ++k) tet[k] = vertex_id(t[k], "tetrahedron index");
    const std::int64_t ref = in_.integer(t[4], "tetrahedron reference");
    if (ref < 0) throw in_.error("tetrahedron reference (piece label) " + std::to_string(ref) + " is negative");
    mesh_.tets.push_back(tet);
    mesh_.labels.push_back(ref);
    mesh_.tet_lines.push_back(in_.line());
  }
}

void MeditParser::ignored(const IgnoredSection& shape, std::size_t count) {
  const std::string name = shape.name;
  for (std::size_t i = 0; i < count; ++i) {
    next_entry(name, i, count);
    in_.expect_tokens(std::size_t(shape.values), name + " entry", std::to_string(shape.values) + " numbers");
    const auto& t = in_.tokens();
    for (int k = 0; k < shape.values; ++k) {
      if (shape.reals) {
        in_.real(t[k], name + " value");
      } else if (k < shape.vertex_ids) {
        vertex_id(t[k], (name + " vertex index").c_str());
      } else if (k < shape.vertex_ids + shape.entity_ids) {
        if (in_.integer(t[k], name + " index") < 1) throw in_.error(name + " index " + quote(t[k]) + " must be >= 1");
      } else {
        in_.integer(t[k], name + " reference");
      }
    }
  }
}

void MeditParser::seen(const std::string& name) {
  if (std::find(sections_.begin(), sections_.end(), name) != sections_.end())
    throw in_.error("section '" + name + "' appears twice");
  sections_.push_back(name);
  previous_ = "section '" + name + "'";
}

void MeditParser::section(std::string_view keyword) {
  for (const char* bad : kUnsupported)
    if (same_word(keyword, bad)) throw in_.error(std::string("section '") + bad + "' is not supported (only tetrahedra)");
  const IgnoredSection* shape = nullptr;
  for (const IgnoredSection& s : kIgnored)
    if (same_word(keyword, s.name)) shape = &s;
  const bool is_vertices = same_word(keyword, "Vertices"), is_tets = same_word(keyword, "Tetrahedra");
  if (!shape && !is_vertices && !is_tets) {
    if (looks_numeric(keyword))
      throw in_.error("expected a section keyword, found " + quote(keyword) + " (more entries than the count of " +
                      previous_ + " announced?)");
    throw in_.error("unknown section " + quote(keyword));
  }
  const std::string name = is_vertices ? "Vertices" : is_tets ? "Tetrahedra" : shape->name;
  seen(name);
  const bool names_vertices = is_tets || (shape && shape->vertex_ids > 0);
  if (names_vertices && !have_vertices_)
    throw in_.error("section '" + name + "' comes before section 'Vertices' (its indices name vertices)");
  const std::size_t count = section_count(name);
  if (is_vertices) vertices(count);
  else if (is_tets) tetrahedra(count);
  else ignored(*shape, count);
}

TetMesh MeditParser::parse() {
  const std::int64_t version = keyword_value("MeshVersionFormatted");
  if (version < 1 || version > 3) throw in_.error("MeshVersionFormatted " + std::to_string(version) + " is not 1, 2 or 3");
  const std::int64_t dimension = keyword_value("Dimension");
  if (dimension != 3) throw in_.error("Dimension " + std::to_string(dimension) + " is not supported (only 3)");
  bool ended = false;
  while (in_.next()) {
    const std::string_view keyword = in_.tokens()[0];
    if (same_word(keyword, "End")) {
      if (in_.tokens().size() != 1) throw in_.error("'End' takes no value");
      ended = true;
      break;
    }
    section(keyword);
  }
  if (!ended) throw in_.error("file ends without 'End'");
  if (in_.next()) throw in_.error("data after 'End'");
  if (mesh_.tets.empty()) throw in_.error("the mesh has no tetrahedra (no 'Tetrahedra' section, or its count is 0)");
  return std::move(mesh_);
}

}  // namespace

TetMesh read_medit(const std::filesystem::path& path) {
  const std::string text = io_detail::read_whole_file(path);
  return MeditParser(path.string(), text).parse();
}

}  // namespace fracref
