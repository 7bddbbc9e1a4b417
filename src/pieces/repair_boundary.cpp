// Repairs of S at its boundary that no cut of B can work around: boundary vertices a hair apart
// (a face between them and a trace over a crease of B would have to lie in B) and flaps (faces
// with two boundary edges lying flat on B). Each edit is kept only when S stays valid.
#include <algorithm>
#include <cmath>
#include <set>

#include "geom/intersect.hpp"
#include "pieces/pieces_internal.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref::pieces_detail {
namespace {

// S with new faces, if the result is valid.
bool try_faces(FractureSurface& s, std::vector<glm::uvec4> faces, std::vector<glm::ivec2> pieces,
               std::vector<std::uint32_t>& origin, std::vector<std::uint32_t> new_origin) {
  FractureSurface candidate = s;
  candidate.faces = std::move(faces);
  candidate.face_pieces = std::move(pieces);
  rebuild_adjacency(candidate);
  if (!validate_rebuilt(candidate).empty()) return false;
  s = std::move(candidate);
  origin = std::move(new_origin);
  return true;
}

// Whether the faces `changed` of `faces` meet no other face except where they connect (exact).
// A linear scan with a box test: collapses are few, and a tree per collapse would cost more.
bool clear_of_the_rest(const std::vector<glm::dvec3>& x, const std::vector<glm::uvec4>& faces,
                       const std::vector<std::uint32_t>& changed) {
  auto box = [&](const glm::uvec4& f, glm::dvec3& lo, glm::dvec3& hi) {
    lo = glm::min(glm::min(x[f.x], x[f.y]), x[f.z]);
    hi = glm::max(glm::max(x[f.x], x[f.y]), x[f.z]);
  };
  for (std::uint32_t c : changed) {
    glm::dvec3 lo, hi, glo, ghi;
    box(faces[c], lo, hi);
    for (std::uint32_t g = 0; g < faces.size(); ++g) {
      box(faces[g], glo, ghi);
      if (g == c || glm::any(glm::lessThan(ghi, lo)) || glm::any(glm::greaterThan(glo, hi))) continue;
      if (mesh_faces_intersect(x, {faces[c].x, faces[c].y, faces[c].z}, {faces[g].x, faces[g].y, faces[g].z}))
        return false;
    }
  }
  return true;
}

bool remove_face(FractureSurface& s, std::vector<std::uint32_t>& origin, std::uint32_t face) {
  std::vector<glm::uvec4> faces = s.faces;
  std::vector<glm::ivec2> pieces = s.face_pieces;
  std::vector<std::uint32_t> new_origin = origin;
  faces.erase(faces.begin() + face);
  pieces.erase(pieces.begin() + face);
  new_origin.erase(new_origin.begin() + face);
  return try_faces(s, std::move(faces), std::move(pieces), origin, std::move(new_origin));
}

glm::dvec3 at(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }

// The end of boundary edge a-b that a collapse keeps: the kVertexOriginal one, else a.
std::pair<std::uint32_t, std::uint32_t> gone_and_kept(const FractureSurface& s, std::uint32_t a, std::uint32_t b) {
  const bool keep_b = (s.vertex_flags[b] & kVertexOriginal) && !(s.vertex_flags[a] & kVertexOriginal);
  return keep_b ? std::pair{a, b} : std::pair{b, a};
}

// Contractions (gone, keep) made together: the faces on each edge vanish, the others of the
// removed end move to the kept one; false, changing nothing, when a moved face would meet
// another face (the faces around a removed end swing over to the kept one, across whatever lies
// between) or S would be invalid.
bool contract_all(FractureSurface& s, std::vector<std::uint32_t>& origin,
                  const std::vector<std::pair<std::uint32_t, std::uint32_t>>& batch) {
  std::vector<std::uint32_t> to(s.positions.size());
  for (std::uint32_t v = 0; v < to.size(); ++v) to[v] = v;
  for (const auto& [gone, keep] : batch) to[gone] = keep;
  std::vector<glm::uvec4> faces;
  std::vector<glm::ivec2> pieces;
  std::vector<std::uint32_t> new_origin, changed;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const glm::uvec4 t(to[s.faces[f].x], to[s.faces[f].y], to[s.faces[f].z], s.faces[f].w);
    if (t.x == t.y || t.y == t.z || t.z == t.x) continue;
    if (t != s.faces[f]) changed.push_back(std::uint32_t(faces.size()));
    faces.push_back(t);
    pieces.push_back(s.face_pieces[f]);
    new_origin.push_back(origin[f]);
  }
  if (!clear_of_the_rest(double_positions(s), faces, changed)) return false;
  return try_faces(s, std::move(faces), std::move(pieces), origin, std::move(new_origin));
}

// As many of the contractions (of edges whose neighbourhoods do not touch) as can be made: all at
// once, or else each half of them so, recursively. One at a time, a batch of n with one refused
// contraction in it would cost n rebuilds of S; halving costs about 2 log2 n. Returns how many were made.
std::uint32_t contract_halving(FractureSurface& s, std::vector<std::uint32_t>& origin,
                               const std::vector<std::pair<std::uint32_t, std::uint32_t>>& batch) {
  if (batch.empty()) return 0;
  if (contract_all(s, origin, batch)) return std::uint32_t(batch.size());
  if (batch.size() == 1) return 0;
  const auto middle = batch.begin() + std::ptrdiff_t(batch.size() / 2);
  return contract_halving(s, origin, {batch.begin(), middle}) + contract_halving(s, origin, {middle, batch.end()});
}

// The vertices of the faces around chosen vertices, marked: an edit whose neighbourhood touches
// none marked so far can be made together with the ones marked (their faces are apart).
class Neighbourhoods {
 public:
  explicit Neighbourhoods(const FractureSurface& s) : s_(s), marked_(s.positions.size(), 0) {}
  bool free(std::uint32_t a, std::uint32_t b) const {
    bool free = true;
    for (std::uint32_t v : {a, b}) ring(v, [&](std::uint32_t w) { free = free && !marked_[w]; });
    return free;
  }
  void mark(std::uint32_t a, std::uint32_t b) {
    for (std::uint32_t v : {a, b}) ring(v, [&](std::uint32_t w) { marked_[w] = 1; });
  }

 private:
  template <class Visit>
  void ring(std::uint32_t v, Visit&& visit) const {
    for (std::uint32_t k = s_.vf_offsets[v]; k < s_.vf_offsets[v + 1]; ++k)
      for (int c = 0; c < 3; ++c) visit(s_.faces[s_.vf_faces[k]][c]);
  }
  const FractureSurface& s_;
  std::vector<char> marked_;
};

// The contractions (gone, keep) in order, made in rounds: a contraction whose neighbourhood
// touches none of an earlier one still waiting joins the round, and a round is made with one
// rebuild of S (in halves when that fails). One rebuild per contraction made the
// pieces stage's repair cost grow with the square of its retries (65 attempts in 6 minutes).
void contract_in_rounds(FractureSurface& s, RepairReport& report,
                        std::vector<std::pair<std::uint32_t, std::uint32_t>> pending) {
  while (!pending.empty()) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> round, later;
    Neighbourhoods taken(s);
    for (const auto& c : pending) {
      if (std::max(c.first, c.second) >= s.positions.size()) continue;  // no vertices, so no edge, of S
      const bool free = taken.free(c.first, c.second);
      taken.mark(c.first, c.second);  // a waiting contraction holds back the later ones it touches
      if (!free) later.push_back(c);
      else if (find_edge(s, c.first, c.second) != kNoEdge) round.push_back(c);
    }
    report.contracted += contract_halving(s, report.face_origin, round);
    pending = std::move(later);
  }
}

// One pass over the boundary edges shorter than min_length, shortest first, but for those
// refused before; true if any went or was newly refused. Every rebuild and validation of S costs
// a pass over all of it, so the collapses whose neighbourhoods do not touch are made together (in
// halves when that fails); those touching one of them wait for the next pass.
bool collapse_pass(FractureSurface& s, std::vector<std::uint32_t>& origin, double min_length, std::uint32_t& count,
                   std::set<std::pair<std::uint32_t, std::uint32_t>>& refused) {
  std::vector<std::pair<double, glm::uvec2>> shortest;
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    const double len = glm::length(at(s, s.edges[e].x) - at(s, s.edges[e].y));
    if (s.edge_special[e] == kEdgeBoundary && len < min_length && !refused.count({s.edges[e].x, s.edges[e].y}))
      shortest.emplace_back(len, s.edges[e]);
  }
  std::sort(shortest.begin(), shortest.end(), [](const auto& x, const auto& y) {
    return x.first < y.first || (x.first == y.first && (x.second.x < y.second.x || (x.second.x == y.second.x && x.second.y < y.second.y)));
  });
  std::vector<std::pair<std::uint32_t, std::uint32_t>> batch;
  std::vector<glm::uvec2> batch_edges;
  Neighbourhoods taken(s);
  for (const auto& [len, e] : shortest) {
    if (!taken.free(e.x, e.y)) continue;
    taken.mark(e.x, e.y);
    batch.push_back(gone_and_kept(s, e.x, e.y));
    batch_edges.push_back(e);
  }
  const std::uint32_t made = contract_halving(s, origin, batch);
  count += made;
  if (made == batch.size()) return made > 0;
  // A collapse made removes its edge (the batch's neighbourhoods do not touch): those still
  // there were refused, and are not tried again.
  const std::size_t known = refused.size();
  for (const glm::uvec2 e : batch_edges)
    if (find_edge(s, e.x, e.y) != kNoEdge) refused.insert({e.x, e.y});
  return made > 0 || refused.size() > known;
}

// Passes until none collapses: a collapse can make a neighbouring boundary edge short.
void collapse_short_edges(FractureSurface& s, std::vector<std::uint32_t>& origin, double min_length,
                          std::uint32_t& count) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> refused;
  while (collapse_pass(s, origin, min_length, count, refused)) {
  }
}

// A face with two or three boundary edges has its corners on B: it lies flat on B when its
// centroid does too, or when it is a needle (its corners nearly in a row along B; its traces
// would wind around its chord).
bool is_flap(const FractureSurface& s, const ExteriorMesh& m, std::uint32_t f, double tolerance) {
  int boundary = 0;
  for (int k = 0; k < 3; ++k) boundary += s.edge_special[s.face_edges[3 * f + k]] == kEdgeBoundary;
  if (boundary < 2) return false;
  const glm::dvec3 a = at(s, s.faces[f].x), b = at(s, s.faces[f].y), c = at(s, s.faces[f].z);
  const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
  if (glm::length(glm::cross(b - a, c - a)) < kNeedle * longest * longest) return true;
  const double distance = std::sqrt(closest_point(m.bvh, (a + b + c) / 3.0).squared_distance);
  return distance <= 0.01 * longest + tolerance;
}

// All of `faces` (ascending) removed at once; false, changing nothing, when S would be invalid.
bool remove_faces(FractureSurface& s, std::vector<std::uint32_t>& origin, const std::vector<std::uint32_t>& faces) {
  std::vector<glm::uvec4> kept;
  std::vector<glm::ivec2> pieces;
  std::vector<std::uint32_t> new_origin;
  std::size_t next = 0;
  for (std::uint32_t f = 0; f < s.faces.size(); ++f) {
    if (next < faces.size() && faces[next] == f) {
      ++next;
      continue;
    }
    kept.push_back(s.faces[f]);
    pieces.push_back(s.face_pieces[f]);
    new_origin.push_back(origin[f]);
  }
  return try_faces(s, std::move(kept), std::move(pieces), origin, std::move(new_origin));
}

// Every rebuild and validation of S costs a pass over all of it, so the flaps found in one scan
// are removed together; only when that would leave S invalid are they removed one at a time
// (the first removable one, then a new scan), as removing one can make its neighbour a flap.
void remove_flaps(FractureSurface& s, std::vector<std::uint32_t>& origin, const ExteriorMesh& m, double tolerance,
                  std::uint32_t& count) {
  for (;;) {
    std::vector<std::uint32_t> flaps;
    for (std::uint32_t f = 0; f < s.faces.size(); ++f)
      if (is_flap(s, m, f, tolerance)) flaps.push_back(f);
    if (flaps.empty()) return;
    if (flaps.size() > 1 && remove_faces(s, origin, flaps)) {
      count += std::uint32_t(flaps.size());
      continue;
    }
    bool removed = false;
    for (std::uint32_t f : flaps)
      if (remove_face(s, origin, f)) {
        removed = true, ++count;
        break;
      }
    if (!removed) return;
  }
}

}  // namespace

FractureSurface repair_boundary(FractureSurface s, const ExteriorMesh& m, double min_edge, bool flaps,
                                double tolerance, const std::vector<std::uint32_t>& left_out,
                                const std::vector<std::pair<std::uint32_t, std::uint32_t>>& contractions,
                                RepairReport& report) {
  FractureSurface out = std::move(s);
  report.face_origin.resize(out.faces.size());
  for (std::uint32_t f = 0; f < out.faces.size(); ++f) report.face_origin[f] = f;
  contract_in_rounds(out, report, contractions);
  if (min_edge > 0.0) collapse_short_edges(out, report.face_origin, min_edge, report.collapsed);
  if (!flaps) return out;
  for (std::uint32_t face : left_out) {
    const auto it = std::find(report.face_origin.begin(), report.face_origin.end(), face);
    if (it != report.face_origin.end() && remove_face(out, report.face_origin, std::uint32_t(it - report.face_origin.begin())))
      ++report.flaps_removed;
  }
  remove_flaps(out, report.face_origin, m, tolerance, report.flaps_removed);
  return out;
}

}  // namespace fracref::pieces_detail
