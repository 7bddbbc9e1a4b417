// The coarse model of a labelled tet mesh: faces, cuts, virtual fracture, pieces, S and hull.
#include <algorithm>
#include <map>
#include <array>
#include <cctype>
#include <cmath>
#include <string>

#include "coarse/coarse_internal.hpp"
#include "coarse/coarse_model.hpp"
#include "coarse/tet_readers.hpp"
#include "coarse/virtual_fracture.hpp"
#include "coarse/tet_tables.hpp"
#include "geom/predicates.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {
using namespace coarse_detail;

struct FaceSide {
  std::uint32_t tet = 0;
  std::uint8_t local = 0;
};

struct FaceUse {
  glm::uvec3 key;
  FaceSide side;
};

class TetBuilder {
 public:
  TetBuilder(const TetMesh& mesh, const CrackList* cracks, const TetModelOptions& options)
      : mesh_(mesh), cracks_(cracks), options_(options), source_(mesh.file.empty() ? "tet mesh" : mesh.file) {}
  CoarseModel build();

 private:
  InputError tet_error(std::uint32_t t, const std::string& what) const;
  std::string tet_name(std::uint32_t t) const;
  void check_input();
  void weld_and_orient();
  void collect_faces();
  void add_face_group(const std::vector<FaceUse>& uses, std::size_t begin, std::size_t end);
  void mark_cracks();
  void flood_pieces();
  void check_separation() const;
  void emit();

  glm::uvec3 model_face(FaceSide s) const {
    const glm::uvec4& t = m_.tets[s.tet];
    return {t[kTetFaces[s.local][0]], t[kTetFaces[s.local][1]], t[kTetFaces[s.local][2]]};
  }
  glm::uvec3 welded(glm::uvec3 f) const { return {m_.vertex_weld[f.x], m_.vertex_weld[f.y], m_.vertex_weld[f.z]}; }
  std::string face_text(const glm::uvec3& f) const {
    return point_text(m_.vertices[f.x]) + " " + point_text(m_.vertices[f.y]) + " " + point_text(m_.vertices[f.z]);
  }

  const TetMesh& mesh_;
  const CrackList* cracks_;
  TetModelOptions options_;
  std::string source_;
  CoarseModel m_;
  std::vector<int> label_;  // compact label per tet
  std::vector<std::int64_t> label_values_;
  std::vector<glm::uvec3> interior_, interior_keys_, hull_keys_;
  std::vector<std::array<FaceSide, 2>> interior_sides_;
  std::vector<FaceSide> hull_sides_;
  std::vector<std::uint8_t> cut_;
  std::vector<std::size_t> crack_line_;  // per interior face: the cracks-file line that cut it, 0 if none
};

std::string TetBuilder::tet_name(std::uint32_t t) const {
  if (mesh_.tet_lines.size() == mesh_.tets.size()) return "the tet of line " + std::to_string(mesh_.tet_lines[t]);
  return "tet " + std::to_string(t);
}

InputError TetBuilder::tet_error(std::uint32_t t, const std::string& what) const {
  if (!mesh_.file.empty() && mesh_.tet_lines.size() == mesh_.tets.size())
    return input_error_at(mesh_.file, mesh_.tet_lines[t], what);
  return InputError(source_ + ": tet " + std::to_string(t) + ": " + what);
}

void TetBuilder::check_input() {
  if (mesh_.tets.empty()) throw InputError(source_ + ": the mesh has no tetrahedra");
  if (mesh_.labels.size() != mesh_.tets.size())
    throw InputError(source_ + ": " + std::to_string(mesh_.labels.size()) + " labels for " +
                     std::to_string(mesh_.tets.size()) + " tetrahedra");
  for (std::size_t v = 0; v < mesh_.vertices.size(); ++v)
    if (!finite(mesh_.vertices[v]))
      throw InputError(source_ + ": vertex " + std::to_string(v) + " is not finite");
  const std::size_t nv = mesh_.vertices.size();
  for (std::uint32_t t = 0; t < mesh_.tets.size(); ++t) {
    for (int i = 0; i < 4; ++i)
      if (mesh_.tets[t][i] >= nv)
        throw tet_error(t, "vertex " + std::to_string(mesh_.tets[t][i]) + " is out of range (" +
                               std::to_string(nv) + " vertices)");
    if (mesh_.labels[t] < 0) throw tet_error(t, "piece label " + std::to_string(mesh_.labels[t]) + " is negative");
  }
  label_values_ = mesh_.labels;
  std::sort(label_values_.begin(), label_values_.end());
  label_values_.erase(std::unique(label_values_.begin(), label_values_.end()), label_values_.end());
  label_.resize(mesh_.tets.size());
  for (std::size_t t = 0; t < label_.size(); ++t)
    label_[t] = int(std::lower_bound(label_values_.begin(), label_values_.end(), mesh_.labels[t]) - label_values_.begin());
}

void TetBuilder::weld_and_orient() {
  m_.vertices = mesh_.vertices;
  m_.tets = mesh_.tets;
  m_.vertex_weld = weld_points(m_.vertices, options_.weld_tolerance * bbox_diagonal(m_.vertices));
  for (std::uint32_t t = 0; t < m_.tets.size(); ++t) {
    glm::uvec4& tet = m_.tets[t];
    const glm::uvec4 w(m_.vertex_weld[tet.x], m_.vertex_weld[tet.y], m_.vertex_weld[tet.z], m_.vertex_weld[tet.w]);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (w[i] == w[j])
          throw tet_error(t, "tetrahedron has zero volume: its vertices " + std::to_string(tet[i]) + " and " +
                                 std::to_string(tet[j]) + " coincide at " + point_text(m_.vertices[w[i]]));
    const int sign = orient3d(m_.vertices[w.x], m_.vertices[w.y], m_.vertices[w.z], m_.vertices[w.w]);
    if (sign == 0)
      throw tet_error(t, "tetrahedron has zero volume (its four vertices " + point_text(m_.vertices[w.x]) + " " +
                             point_text(m_.vertices[w.y]) + " " + point_text(m_.vertices[w.z]) + " " +
                             point_text(m_.vertices[w.w]) + " are coplanar)");
    if (sign > 0) {  // orient3d > 0: d below abc, i.e. negative volume
      std::swap(tet.z, tet.w);
      ++m_.inverted_fixed;
    }
  }
}

void TetBuilder::add_face_group(const std::vector<FaceUse>& uses, std::size_t begin, std::size_t end) {
  const FaceSide first = uses[begin].side;
  if (end - begin == 1) {
    hull_sides_.push_back(first);
    hull_keys_.push_back(uses[begin].key);
    return;
  }
  const FaceSide second = uses[begin + 1].side;
  if (end - begin > 2)
    throw tet_error(uses[begin + 2].side.tet,
                    "face " + face_text(uses[begin].key) + " is shared by " + std::to_string(end - begin) +
                        " tetrahedra (" + tet_name(first.tet) + ", " + tet_name(second.tet) + " and " +
                        tet_name(uses[begin + 2].side.tet) + "); a face bounds at most two");
  const glm::uvec3 w0 = welded(model_face(first)), w1 = welded(model_face(second));
  if (same_winding(w0, w1))
    throw tet_error(second.tet, "tetrahedron overlaps " + tet_name(first.tet) + ": both lie on the same side of their face " +
                                    face_text(uses[begin].key));
  interior_.push_back(w0);
  interior_keys_.push_back(uses[begin].key);
  interior_sides_.push_back({first, second});
  // Different labels, or different vertex copies (a crack the simulator opened): a cut.
  const bool opened = sorted_key(model_face(first)) != sorted_key(model_face(second));
  cut_.push_back(label_[first.tet] != label_[second.tet] || opened);
  crack_line_.push_back(0);
}

void TetBuilder::collect_faces() {
  std::vector<FaceUse> uses;
  uses.reserve(m_.tets.size() * 4);
  for (std::uint32_t t = 0; t < m_.tets.size(); ++t)
    for (std::uint8_t l = 0; l < 4; ++l) uses.push_back({sorted_key(welded(model_face({t, l}))), {t, l}});
  std::sort(uses.begin(), uses.end(), [](const FaceUse& x, const FaceUse& y) {
    if (x.key != y.key) return key_less(x.key, y.key);
    return x.side.tet != y.side.tet ? x.side.tet < y.side.tet : x.side.local < y.side.local;
  });
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    add_face_group(uses, i, j);
    i = j;
  }
}

void TetBuilder::mark_cracks() {
  if (!cracks_) return;
  const CrackList& c = *cracks_;
  for (std::size_t i = 0; i < c.faces.size(); ++i) {
    const std::size_t line = i < c.lines.size() ? c.lines[i] : i + 1;
    const glm::uvec3 f = c.faces[i];
    const std::string name = "face " + std::to_string(f.x) + " " + std::to_string(f.y) + " " + std::to_string(f.z);
    for (int k = 0; k < 3; ++k)
      if (f[k] >= m_.vertices.size())
        throw input_error_at(c.file, line, "vertex id " + std::to_string(f[k]) + " is out of range (the mesh has " +
                                               std::to_string(m_.vertices.size()) + " vertices; ids start at 0)");
    const glm::uvec3 key = sorted_key(welded(f));
    if (key.x == key.y || key.y == key.z) throw input_error_at(c.file, line, name + " repeats a vertex");
    auto it = std::lower_bound(interior_keys_.begin(), interior_keys_.end(), key, key_less);
    if (it == interior_keys_.end() || *it != key) {
      const bool on_hull = std::binary_search(hull_keys_.begin(), hull_keys_.end(), key, key_less);
      throw input_error_at(c.file, line, name + (on_hull ? " is on the exterior of the mesh, not an interior face"
                                                         : " is not a face of any tetrahedron"));
    }
    const std::size_t face = std::size_t(it - interior_keys_.begin());
    const auto& sides = interior_sides_[face];
    if (label_[sides[0].tet] != label_[sides[1].tet])
      throw input_error_at(c.file, line, name + " lies between pieces already (labels " +
                                             std::to_string(mesh_.labels[sides[0].tet]) + " and " +
                                             std::to_string(mesh_.labels[sides[1].tet]) +
                                             "); list only faces inside one piece");
    if (crack_line_[face]) throw input_error_at(c.file, line, name + " repeats the crack of line " + std::to_string(crack_line_[face]));
    cut_[face] = 1;
    crack_line_[face] = line;
  }
}

void TetBuilder::flood_pieces() {
  MinUnion sets(m_.tets.size());
  for (std::size_t f = 0; f < interior_sides_.size(); ++f)
    if (!cut_[f]) sets.unite(interior_sides_[f][0].tet, interior_sides_[f][1].tet);
  const int labels = int(label_values_.size());
  std::vector<int> parts(labels, 0);
  m_.piece_names.resize(labels);
  m_.piece_count = labels;
  m_.tet_piece.assign(m_.tets.size(), -1);
  for (std::uint32_t t = 0; t < m_.tets.size(); ++t) {
    const std::uint32_t root = sets.find(t);
    if (root != t) {  // the root is the component's lowest tet, already numbered
      m_.tet_piece[t] = m_.tet_piece[root];
      continue;
    }
    const int label = label_[t];
    const std::string name = "label " + std::to_string(label_values_[label]);
    if (parts[label]++ == 0) {
      m_.tet_piece[t] = label;
      m_.piece_names[label] = name;
    } else {
      m_.tet_piece[t] = m_.piece_count++;
      m_.piece_names.push_back(name + ", part " + std::to_string(parts[label]));
    }
  }
}

void TetBuilder::check_separation() const {
  for (std::size_t f = 0; f < interior_sides_.size(); ++f) {
    const int piece = m_.tet_piece[interior_sides_[f][0].tet];
    if (!cut_[f] || piece != m_.tet_piece[interior_sides_[f][1].tet]) continue;
    const std::string why =
        options_.virtual_fracture
            ? " even after virtual fracture (the cut goes around a handle of the piece without cutting through it)"
            : " and virtual fracture is off: enable it or list the faces that complete the cut";
    const std::string what = "the cut through face " + face_text(interior_keys_[f]) + " does not separate piece '" +
                             m_.piece_names[piece] + "'" + why;
    if (crack_line_[f]) throw input_error_at(cracks_->file, crack_line_[f], what);
    throw InputError(source_ + ": " + what);
  }
}

// Corners of `model` (a face of one tet, any winding) reordered to match `target` (welded ids).
glm::uvec3 align_corners(const glm::uvec3& model, const glm::uvec3& target, const std::vector<std::uint32_t>& weld) {
  glm::uvec3 out = model;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (weld[model[j]] == target[i]) out[i] = model[j];
  return out;
}

void TetBuilder::emit() {
  std::vector<SurfaceFace> faces;
  for (std::size_t f = 0; f < interior_sides_.size(); ++f) {
    if (!cut_[f]) continue;
    FaceSide back = interior_sides_[f][0], front = interior_sides_[f][1];
    if (m_.tet_piece[back.tet] > m_.tet_piece[front.tet]) std::swap(back, front);
    SurfaceFace s;
    s.back_model = model_face(back);  // wound outward from the back tet: into the front piece
    s.welded = welded(s.back_model);
    s.front_model = align_corners(model_face(front), s.welded, m_.vertex_weld);
    s.back = m_.tet_piece[back.tet];
    s.front = m_.tet_piece[front.tet];
    faces.push_back(s);
  }
  for (const FaceSide& h : hull_sides_) {
    m_.hull.push_back(model_face(h));
    m_.hull_piece.push_back(m_.tet_piece[h.tet]);
  }
  assemble_surface(m_, faces, source_);
}

CoarseModel TetBuilder::build() {
  check_input();
  weld_and_orient();
  collect_faces();
  mark_cracks();
  if (options_.virtual_fracture) {
    std::vector<glm::uvec3> hull(hull_sides_.size());
    for (std::size_t h = 0; h < hull.size(); ++h) hull[h] = welded(model_face(hull_sides_[h]));
    const VirtualFractureStats stats = extend_cracks(m_.vertices, interior_, hull, cut_);
    m_.virtual_faces_added = stats.faces_added;
    m_.virtual_area_added = stats.area_added;
  }
  flood_pieces();
  check_separation();
  emit();
  return std::move(m_);
}

std::string lower_extension(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

namespace {
TetMesh with_vertices_per_label(TetMesh mesh);
}  // namespace

CoarseModel build_tet_model(const TetMesh& mesh, const CrackList* cracks, const TetModelOptions& options) {
  if (options.own_vertices) return TetBuilder(with_vertices_per_label(mesh), cracks, options).build();
  return TetBuilder(mesh, cracks, options).build();
}

namespace {

// Vertex v stays v for the lowest label using it; every other label using it gets a copy,
// appended in the order (v, label), so the numbering depends only on the mesh.
TetMesh with_vertices_per_label(TetMesh mesh) {
  std::vector<std::pair<std::uint32_t, std::int64_t>> uses;  // (vertex, label)
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int c = 0; c < 4; ++c)
      if (mesh.tets[t][c] < mesh.vertices.size()) uses.emplace_back(mesh.tets[t][c], mesh.labels[t]);
  std::sort(uses.begin(), uses.end());
  uses.erase(std::unique(uses.begin(), uses.end()), uses.end());
  std::map<std::pair<std::uint32_t, std::int64_t>, std::uint32_t> copy;
  for (std::size_t k = 0; k < uses.size(); ++k) {
    if (k == 0 || uses[k].first != uses[k - 1].first) continue;
    copy[uses[k]] = std::uint32_t(mesh.vertices.size());
    mesh.vertices.push_back(mesh.vertices[uses[k].first]);
  }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int c = 0; c < 4; ++c)
      if (const auto it = copy.find({mesh.tets[t][c], mesh.labels[t]}); it != copy.end()) mesh.tets[t][c] = it->second;
  return mesh;
}

}  // namespace

CoarseModel load_tet_model(const std::filesystem::path& mesh, const std::filesystem::path& cracks,
                           const TetModelOptions& options) {
  const std::string ext = lower_extension(mesh);
  TetMesh tets;
  if (ext == ".mesh") tets = read_medit(mesh);
  else if (ext == ".node" || ext == ".ele") tets = read_tetgen(mesh);
  else
    throw InputError(mesh.string() + ": unknown tetrahedral mesh format '" + ext +
                     "' (expected .mesh for MEDIT, .node or .ele for TetGen)");
  if (cracks.empty()) return build_tet_model(tets, nullptr, options);
  const CrackList list = read_cracks(cracks);
  return build_tet_model(tets, &list, options);
}

}  // namespace fracref
