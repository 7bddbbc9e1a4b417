// The coarse model of pre-fractured closed pieces: welding, closedness, matching cut faces,
// the non-conformity check, S and hull.
#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include "coarse/coarse_internal.hpp"
#include "coarse/coarse_model.hpp"
#include "io/mesh_io.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {
using namespace coarse_detail;

struct Tri {
  glm::uvec3 model, welded;
  int piece = 0;
  std::uint32_t polygon = 0;  // numbers the face in its piece, for messages
  bool matched = false;
};

// A polygon of a piece: the fan of triangles [begin, end) of Builder::tris_ and its corner cycle.
struct Polygon {
  int piece = 0;
  std::uint32_t index = 0;
  std::size_t begin = 0, end = 0;
  std::vector<std::uint32_t> cycle;  // welded ids
  std::vector<std::uint32_t> key;    // cycle sorted
};

class PiecesBuilder {
 public:
  PiecesBuilder(const std::vector<PieceInput>& pieces, const PiecesOptions& options) : in_(pieces), options_(options) {}
  CoarseModel build();
  CoarseModel build_checked();

 private:
  InputError piece_error(int p, const std::string& what) const {
    return InputError(in_[p].file + ": piece '" + in_[p].name + "': " + what);
  }
  std::string corners(const glm::uvec3& w) const {
    return point_text(m_.vertices[w.x]) + " " + point_text(m_.vertices[w.y]) + " " + point_text(m_.vertices[w.z]);
  }
  void check_input() const;
  // Per welded cluster (indexed by the concatenated input positions): its representative, the
  // last piece that used it, that piece's model vertex there, and its first (lowest) model vertex.
  struct WeldState {
    std::vector<std::uint32_t> rep;
    std::vector<int> last_piece;
    std::vector<std::uint32_t> model_of, first_model;
  };
  void weld();
  std::vector<std::uint32_t> piece_vertices(int p, std::size_t offset, WeldState& state);
  void add_triangles(int p, const std::vector<std::uint32_t>& local_model);
  void add_polygons(int p, std::size_t first_tri);
  void check_closed(int p) const;
  void orient(int p);
  void match_polygons();
  void match_pair(const Polygon& a, const Polygon& b);
  void match_triangles();
  void add_surface_face(const Tri& back, int front);
  void check_conformity() const;

  const std::vector<PieceInput>& in_;
  PiecesOptions options_;
  CoarseModel m_;
  double diagonal_ = 0.0;
  std::vector<Tri> tris_;
  std::vector<std::size_t> piece_begin_;  // per piece, its first triangle; plus the end
  std::vector<Polygon> polygons_;
  std::vector<std::tuple<std::uint32_t, int, std::uint32_t>> copies_;  // (welded, piece, model), sorted
  std::vector<SurfaceFace> faces_;
  std::vector<std::uint32_t> face_polygon_;  // per face of faces_, its polygon in the back piece
};

void PiecesBuilder::check_input() const {
  if (in_.empty()) throw InputError("pieces: no piece given");
  for (int p = 0; p < int(in_.size()); ++p) {
    const PieceInput& piece = in_[p];
    if (piece.triangles.empty()) throw piece_error(p, "the piece is empty (no faces)");
    if (!piece.triangle_polygon.empty() && piece.triangle_polygon.size() != piece.triangles.size())
      throw piece_error(p, "one polygon index per triangle expected");
    for (const auto& t : piece.triangles)
      for (std::uint32_t v : t)
        if (v >= piece.positions.size()) throw piece_error(p, "vertex " + std::to_string(v) + " out of range");
    for (const glm::dvec3& x : piece.positions)
      if (!finite(x)) throw piece_error(p, "a position is not finite");
  }
}

void PiecesBuilder::weld() {
  std::vector<glm::dvec3> all;
  std::vector<std::size_t> offset;
  for (const PieceInput& piece : in_) {
    offset.push_back(all.size());
    all.insert(all.end(), piece.positions.begin(), piece.positions.end());
  }
  diagonal_ = bbox_diagonal(all);
  WeldState state{weld_points(all, options_.weld_tolerance * diagonal_), std::vector<int>(all.size(), -1),
                  std::vector<std::uint32_t>(all.size()), std::vector<std::uint32_t>(all.size(), UINT32_MAX)};
  for (int p = 0; p < int(in_.size()); ++p) {
    piece_begin_.push_back(tris_.size());
    add_triangles(p, piece_vertices(p, offset[p], state));
    add_polygons(p, piece_begin_.back());
  }
  piece_begin_.push_back(tris_.size());
  std::sort(copies_.begin(), copies_.end());
}

// One model vertex per welded position the piece uses, in the order of its local vertices.
std::vector<std::uint32_t> PiecesBuilder::piece_vertices(int p, std::size_t offset, WeldState& state) {
  const PieceInput& piece = in_[p];
  std::vector<bool> used(piece.positions.size(), false);
  for (const auto& t : piece.triangles) used[t[0]] = used[t[1]] = used[t[2]] = true;
  std::vector<std::uint32_t> local_model(piece.positions.size());
  for (std::uint32_t v = 0; v < piece.positions.size(); ++v) {
    if (!used[v]) continue;
    const std::uint32_t c = state.rep[offset + v];
    if (state.last_piece[c] != p) {
      state.last_piece[c] = p;
      state.model_of[c] = std::uint32_t(m_.vertices.size());
      if (state.first_model[c] == UINT32_MAX) state.first_model[c] = state.model_of[c];
      m_.vertices.push_back(piece.positions[v]);
      m_.vertex_weld.push_back(state.first_model[c]);
      copies_.emplace_back(state.first_model[c], p, state.model_of[c]);
    }
    local_model[v] = state.model_of[c];
  }
  return local_model;
}

void PiecesBuilder::add_triangles(int p, const std::vector<std::uint32_t>& local_model) {
  const PieceInput& piece = in_[p];
  for (std::size_t t = 0; t < piece.triangles.size(); ++t) {
    Tri tri;
    tri.model = {local_model[piece.triangles[t][0]], local_model[piece.triangles[t][1]], local_model[piece.triangles[t][2]]};
    tri.welded = {m_.vertex_weld[tri.model.x], m_.vertex_weld[tri.model.y], m_.vertex_weld[tri.model.z]};
    tri.piece = p;
    tri.polygon = piece.triangle_polygon.empty() ? std::uint32_t(t) : piece.triangle_polygon[t];
    if (tri.welded.x == tri.welded.y || tri.welded.y == tri.welded.z || tri.welded.z == tri.welded.x)
      throw piece_error(p, "face " + std::to_string(tri.polygon) + " is degenerate: corners coincide (" +
                               corners(tri.welded) + ")");
    tris_.push_back(tri);
  }
}

// Splits the piece's triangles into polygons: runs of one polygon index that form a fan
// (v0 v1 v2) (v0 v2 v3) ...; a run that is not a fan becomes one polygon per triangle.
void PiecesBuilder::add_polygons(int p, std::size_t first) {
  for (std::size_t b = first; b < tris_.size();) {
    std::size_t e = b + 1;
    bool fan = true;
    for (; e < tris_.size() && tris_[e].polygon == tris_[b].polygon; ++e)
      fan = fan && tris_[e].welded.x == tris_[b].welded.x && tris_[e].welded.y == tris_[e - 1].welded.z;
    if (!fan) e = b + 1;
    Polygon poly{p, tris_[b].polygon, b, e, {tris_[b].welded.x, tris_[b].welded.y}, {}};
    for (std::size_t t = b; t < e; ++t) poly.cycle.push_back(tris_[t].welded.z);
    poly.key = poly.cycle;
    std::sort(poly.key.begin(), poly.key.end());
    polygons_.push_back(std::move(poly));
    b = e;
  }
}

void PiecesBuilder::check_closed(int p) const {
  std::vector<std::tuple<std::uint32_t, std::uint32_t, bool, std::uint32_t>> edges;  // (min, max, forward, polygon)
  for (std::size_t t = piece_begin_[p]; t < piece_begin_[p + 1]; ++t)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = tris_[t].welded[i], b = tris_[t].welded[(i + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b), a < b, tris_[t].polygon);
    }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && std::get<0>(edges[j]) == std::get<0>(edges[i]) && std::get<1>(edges[j]) == std::get<1>(edges[i])) ++j;
    const std::string edge = "edge " + point_text(m_.vertices[std::get<0>(edges[i])]) + "-" +
                             point_text(m_.vertices[std::get<1>(edges[i])]) + " of face " + std::to_string(std::get<3>(edges[i]));
    if (j - i == 1) throw piece_error(p, "the piece is not closed: " + edge + " is used by no other face of the piece");
    if (j - i > 2) throw piece_error(p, "the piece is not a closed manifold: " + edge + " is used by " + std::to_string(j - i) + " faces");
    if (std::get<2>(edges[i]) == std::get<2>(edges[i + 1]))
      throw piece_error(p, "inconsistent winding: " + edge + " runs the same way in face " + std::to_string(std::get<3>(edges[i + 1])));
    i = j;
  }
}

void PiecesBuilder::orient(int p) {
  const glm::dvec3 o = m_.vertices[tris_[piece_begin_[p]].welded.x];
  double volume = 0.0;
  for (std::size_t t = piece_begin_[p]; t < piece_begin_[p + 1]; ++t) {
    const glm::uvec3 w = tris_[t].welded;
    volume += glm::dot(m_.vertices[w.x] - o, glm::cross(m_.vertices[w.y] - o, m_.vertices[w.z] - o)) / 6.0;
  }
  if (std::abs(volume) <= 1e-12 * diagonal_ * diagonal_ * diagonal_)
    throw piece_error(p, "the piece has zero volume");
  if (volume > 0) return;
  ++m_.inverted_fixed;
  for (std::size_t t = piece_begin_[p]; t < piece_begin_[p + 1]; ++t) {
    std::swap(tris_[t].model.y, tris_[t].model.z);
    std::swap(tris_[t].welded.y, tris_[t].welded.z);
  }
  for (Polygon& poly : polygons_)
    if (poly.piece == p) std::reverse(poly.cycle.begin() + 1, poly.cycle.end());
}

std::uint32_t lookup_copy(const std::vector<std::tuple<std::uint32_t, int, std::uint32_t>>& copies, std::uint32_t welded,
                          int piece) {
  auto it = std::lower_bound(copies.begin(), copies.end(), std::make_tuple(welded, piece, std::uint32_t(0)));
  return std::get<2>(*it);
}

void PiecesBuilder::add_surface_face(const Tri& back, int front) {
  SurfaceFace s;
  s.welded = back.welded;  // wound outward from the back piece: into the front piece
  s.back = back.piece;
  s.front = front;
  s.back_model = back.model;
  for (int i = 0; i < 3; ++i) s.front_model[i] = lookup_copy(copies_, back.welded[i], front);
  faces_.push_back(s);
  face_polygon_.push_back(back.polygon);
}

// Rotations of one cycle are the same polygon; the reversed cycle is the same polygon wound the other way.
bool cyclic_equal(const std::vector<std::uint32_t>& a, std::vector<std::uint32_t> b) {
  for (std::size_t r = 0; r < b.size(); ++r) {
    if (a == b) return true;
    std::rotate(b.begin(), b.begin() + 1, b.end());
  }
  return false;
}

void PiecesBuilder::match_pair(const Polygon& a, const Polygon& b) {
  const std::string both = "pieces '" + in_[a.piece].name + "' and '" + in_[b.piece].name + "'";
  const std::string where = in_[a.piece].file + ": " + both + ": face " + std::to_string(a.index) + " of '" +
                            in_[a.piece].name + "' and face " + std::to_string(b.index) + " of '" + in_[b.piece].name + "'";
  if (a.piece == b.piece) throw piece_error(a.piece, "faces " + std::to_string(a.index) + " and " + std::to_string(b.index) + " lie on the same corners (a repeated face)");
  if (cyclic_equal(a.cycle, b.cycle))
    throw InputError(where + " coincide but are wound the same way: the pieces overlap (each piece must be wound outward)");
  std::vector<std::uint32_t> reversed(b.cycle.rbegin(), b.cycle.rend());
  if (!cyclic_equal(a.cycle, reversed))
    throw InputError(where + " have the same corners in a different order: the cut does not conform");
  for (std::size_t t = a.begin; t < a.end; ++t) tris_[t].matched = true;
  for (std::size_t t = b.begin; t < b.end; ++t) tris_[t].matched = true;
  for (std::size_t t = a.begin; t < a.end; ++t) add_surface_face(tris_[t], b.piece);  // a.piece < b.piece
}

void PiecesBuilder::match_polygons() {
  std::vector<std::uint32_t> order(polygons_.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
    return polygons_[x].key != polygons_[y].key ? polygons_[x].key < polygons_[y].key : x < y;
  });
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i + 1;
    while (j < order.size() && polygons_[order[j]].key == polygons_[order[i]].key) ++j;
    const Polygon& a = polygons_[order[i]];
    if (j - i > 2) {
      const Polygon& c = polygons_[order[i + 2]];
      throw InputError(in_[a.piece].file + ": face " + std::to_string(a.index) + " of '" + in_[a.piece].name +
                       "' is shared by pieces '" + in_[a.piece].name + "', '" + in_[polygons_[order[i + 1]].piece].name +
                       "' and '" + in_[c.piece].name + "'; a cut face separates exactly two pieces");
    }
    if (j - i == 2) match_pair(a, polygons_[order[i + 1]]);
    i = j;
  }
}

void PiecesBuilder::match_triangles() {
  std::vector<std::uint32_t> order;
  for (std::uint32_t t = 0; t < tris_.size(); ++t)
    if (!tris_[t].matched) order.push_back(t);
  auto key = [&](std::uint32_t t) { return sorted_key(tris_[t].welded); };
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return key_less(key(x), key(y)); });
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i + 1;
    while (j < order.size() && key(order[j]) == key(order[i])) ++j;
    if (j - i >= 2) {
      const Tri &a = tris_[order[i]], &b = tris_[order[i + 1]];
      const Polygon pa{a.piece, a.polygon, order[i], order[i] + 1, {a.welded.x, a.welded.y, a.welded.z}, {}};
      const Polygon pb{b.piece, b.polygon, order[i + 1], order[i + 1] + 1, {b.welded.x, b.welded.y, b.welded.z}, {}};
      if (j - i > 2)
        throw InputError(in_[a.piece].file + ": triangle " + corners(a.welded) + " is shared by 3 or more faces of pieces '" +
                         in_[a.piece].name + "', '" + in_[b.piece].name + "' and '" + in_[tris_[order[i + 2]].piece].name + "'");
      match_pair(pa, pb);
    }
    i = j;
  }
}

void PiecesBuilder::check_conformity() const {
  std::vector<ConformFace> faces;
  for (const Tri& t : tris_)
    if (!t.matched) faces.push_back({t.model, t.piece, -1, t.polygon});
  for (std::size_t f = 0; f < faces_.size(); ++f)
    faces.push_back({faces_[f].back_model, faces_[f].back, faces_[f].front, face_polygon_[f]});
  const auto [x, y] = find_nonconforming(m_.vertices, faces, options_.coplanar_tolerance * diagonal_,
                                         options_.weld_tolerance * diagonal_);
  if (x < 0) return;
  const ConformFace &a = faces[x], &b = faces[y];
  const int other = b.piece;
  throw InputError(in_[a.piece].file + ": pieces '" + in_[a.piece].name + "' and '" + in_[other].name +
                   "' do not conform: face " + std::to_string(a.face) + " of '" + in_[a.piece].name + "' (" +
                   corners(a.corners) + ") overlaps face " + std::to_string(b.face) + " of '" + in_[other].name + "' (" +
                   corners(b.corners) + ") in their common plane without matching it vertex for vertex " +
                   "(a T-junction or a partial overlap); cut faces must coincide exactly");
}

CoarseModel PiecesBuilder::build() {
  check_input();
  try {
    return build_checked();
  } catch (const PiecesMismatch&) {
    throw;
  } catch (const InputError& e) {
    throw PiecesMismatch(e.what());  // well-formed pieces that do not conform: pieces_fit.hpp can fit them
  }
}

CoarseModel PiecesBuilder::build_checked() {
  weld();
  m_.piece_count = int(in_.size());
  for (int p = 0; p < m_.piece_count; ++p) {
    check_closed(p);
    orient(p);
    m_.piece_names.push_back(in_[p].name);
  }
  match_polygons();
  match_triangles();
  for (const Tri& t : tris_)
    if (!t.matched) m_.hull.push_back(t.model), m_.hull_piece.push_back(t.piece);
  check_conformity();
  assemble_surface(m_, faces_, in_[0].file);
  return std::move(m_);
}

// One piece per OBJ group, its vertices compacted and its polygons renumbered from 0.
PieceInput group_piece(const MeshSoup& soup, std::uint32_t group, const std::string& file) {
  PieceInput piece;
  piece.name = soup.groups[group];
  piece.file = file;
  std::vector<std::uint32_t> local(soup.positions.size(), UINT32_MAX);
  std::uint32_t last_polygon = UINT32_MAX, polygons = 0;
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    if (soup.triangle_group[t] != group) continue;
    std::array<std::uint32_t, 3> tri{};
    for (int i = 0; i < 3; ++i) {
      std::uint32_t& l = local[soup.triangles[t][i]];
      if (l == UINT32_MAX) l = std::uint32_t(piece.positions.size()), piece.positions.push_back(soup.positions[soup.triangles[t][i]]);
      tri[i] = l;
    }
    if (soup.triangle_polygon[t] != last_polygon) last_polygon = soup.triangle_polygon[t], ++polygons;
    piece.triangles.push_back(tri);
    piece.triangle_polygon.push_back(polygons - 1);
  }
  return piece;
}

}  // namespace

CoarseModel build_pieces_model(const std::vector<PieceInput>& pieces, const PiecesOptions& options) {
  return PiecesBuilder(pieces, options).build();
}

std::vector<PieceInput> read_pieces(const std::filesystem::path& obj) {
  const MeshSoup soup = read_mesh(obj);
  if (soup.groups.empty())
    throw InputError(obj.string() + ": no 'o' or 'g' groups: a pieces file needs one group per piece");
  std::vector<PieceInput> pieces;
  for (std::uint32_t g = 0; g < soup.groups.size(); ++g) pieces.push_back(group_piece(soup, g, obj.string()));
  return pieces;
}

std::vector<PieceInput> read_pieces(const std::vector<std::filesystem::path>& files) {
  if (files.empty()) throw InputError("pieces: no piece file given");
  std::vector<PieceInput> pieces;
  for (const auto& file : files) {
    MeshSoup soup = read_mesh(file);
    PieceInput piece;
    piece.name = file.filename().string();
    piece.file = file.string();
    piece.positions = std::move(soup.positions);
    piece.triangles = std::move(soup.triangles);
    piece.triangle_polygon = std::move(soup.triangle_polygon);
    pieces.push_back(std::move(piece));
  }
  return pieces;
}

CoarseModel load_pieces(const std::filesystem::path& obj, const PiecesOptions& options) {
  return build_pieces_model(read_pieces(obj), options);
}

CoarseModel load_pieces(const std::vector<std::filesystem::path>& files, const PiecesOptions& options) {
  return build_pieces_model(read_pieces(files), options);
}

}  // namespace fracref
