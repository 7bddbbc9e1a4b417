// build_pieces: snap, trace, insert, patches, merge (pieces.hpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "pieces/pieces.hpp"
#include "pieces/pieces_internal.hpp"
#include "pieces/retries.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using namespace pieces_detail;
using Tri = std::array<std::uint32_t, 3>;
using DirectedEdge = std::pair<std::uint32_t, std::uint32_t>;

// Attempts build_pieces makes (leaving out flaps, re-tracing, pushing) before it gives up.
constexpr std::size_t kMaxAttempts = 64;
// Pokes out of B shallower than this (relative to B's diagonal) are float noise.
constexpr double kPokeTolerance = 1e-6;
// A vertex is pushed inward at most this fraction of its shortest edge, in this many rounds.
constexpr double kMaxPush = 1.0;
// A fracture triangle crossing a B triangle pushes its S vertices off B this fraction of their
// shortest edge per attempt (one crossing another fracture triangle: see kRelaxStep).
constexpr double kClashPush = 0.1;

std::string vertex_pair(std::uint32_t a, std::uint32_t b) { return std::to_string(a) + "-" + std::to_string(b); }

// S with its derived arrays rebuilt (a caller may hand it over stale), if its invariants hold.
FractureSurface checked(const FractureSurface& s) {
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const glm::uvec4 t = s.faces[f];
    const bool bad = t.x >= s.positions.size() || t.y >= s.positions.size() || t.z >= s.positions.size() ||
                     t.x == t.y || t.y == t.z || t.z == t.x;
    if (bad) throw RunError("the fracture surface is not valid: " + validate(s));
  }
  FractureSurface copy = s;
  rebuild_adjacency(copy);
  const std::string problem = validate_rebuilt(copy);  // validate() would rebuild it a second time
  if (!problem.empty()) throw RunError("the fracture surface is not valid: " + problem);
  return copy;
}

// S after repair_boundary with the retries' flaps and contractions. Most retries change
// neither (they push vertices), and the repair costs as much as the rest of an attempt on a large
// S, so build_pieces keeps it while they stay the same.
struct RepairedInput {
  std::vector<std::uint32_t> left_out;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> contractions;
  RepairReport report;
  FractureSurface s;

  bool made_for(const Retries& r) const { return left_out == r.left_out && contractions == r.contractions; }
};

RepairedInput repair_input(const FractureSurface& s, const ExteriorMesh& m, const PieceOptions& options, const Retries& retries) {
  RepairedInput r{retries.left_out, retries.contractions, {}, {}};
  r.s = repair_boundary(s, m, options.merge_tolerance * m.diagonal, options.remove_flaps, options.snap_tolerance * m.diagonal,
                        retries.left_out, retries.contractions, r.report);
  return r;
}

class PieceBuilder {
 public:
  PieceBuilder(const RepairedInput& repaired, const ExteriorMesh& m, const PieceOptions& options, const Retries& retries)
      : m_(m), options_(options), retries_(retries), repair_(repaired.report), s_(repaired.s) {
    out_.boundary_edges_merged = repair_.collapsed;
    out_.flaps_removed = repair_.flaps_removed;
    out_.contracted = repair_.contracted;
    out_.rim_retracted = retract_rim(s_, m_, kPokeTolerance * m_.diagonal);
    push_inward(s_, m_, retries.pushed);
    out_.pushed_inward = std::uint32_t(retries.pushed.size());
    relax_toward_neighbours(s_, retries.relaxed);
    out_.relaxed = std::uint32_t(retries.relaxed.size());
  }

  PieceSet run() {
    init_vertices();
    snap_boundary();
    add_exterior_vertices();
    trace_boundary();
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e)
      if (s_.edge_special[e] != kEdgeBoundary && cut_.on_b[s_.edges[e].x] && cut_.on_b[s_.edges[e].y])
        cut_.chords.insert({std::min(s_.edges[e].x, s_.edges[e].y), std::max(s_.edges[e].x, s_.edges[e].y)});
    b_triangles_ = cut_exterior(m_, cut_, out_.positions, options_.delaunay);
    remesh_fracture_faces();
    check_poking();
    check_clashes();
    assemble(assign_patches());
    return std::move(out_);
  }

 private:
  std::uint32_t new_vertex(const glm::dvec3& p, std::int64_t origin, const Location* loc) {
    const std::uint32_t id = std::uint32_t(out_.positions.size());
    out_.positions.push_back(p);
    out_.vertex_origin.push_back(origin);
    cut_.location.push_back(loc ? *loc : Location{});
    cut_.on_b.push_back(loc ? 1 : 0);
    return id;
  }

  void init_vertices() {
    out_.s_vertex_count = std::uint32_t(s_.positions.size());
    for (std::uint32_t v = 0; v < s_.positions.size(); ++v) new_vertex(glm::dvec3(s_.positions[v]), v, nullptr);
    b_owner_.assign(m_.positions.size(), kNone);
  }

  void snap_boundary() {
    std::vector<char> boundary(s_.positions.size(), 0);
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e)
      if (s_.edge_special[e] == kEdgeBoundary) boundary[s_.edges[e].x] = boundary[s_.edges[e].y] = 1;
    const double tolerance = options_.snap_tolerance * m_.diagonal;
    for (std::uint32_t v = 0; v < boundary.size(); ++v) {
      if (!boundary[v]) continue;
      double distance = 0.0;
      const Location loc = locate_on_exterior(m_, out_.positions[v], options_.location_epsilon, &distance);
      if (!(distance <= tolerance))
        throw RunError("fracture surface boundary vertex " + std::to_string(v) + " at " + format_point(out_.positions[v]) +
                       " is " + std::to_string(distance) + " from the exterior (tolerance " + std::to_string(tolerance) +
                       "): the fracture surface must end on the exterior");
      if (loc.kind == Location::kVertex) {
        if (b_owner_[loc.id] != kNone)
          throw RunError("fracture surface vertices " + std::to_string(b_owner_[loc.id]) + " and " + std::to_string(v) +
                         " both lie on exterior vertex " + std::to_string(loc.id) + " at " + format_point(loc.point));
        b_owner_[loc.id] = v;
        ++out_.snapped_to_b_vertex;
      } else if (loc.kind == Location::kEdge) {
        cut_.edge_points[loc.id].emplace_back(loc.t, v);
      } else {
        cut_.face_points[loc.id].push_back(v);
      }
      out_.positions[v] = loc.point;
      cut_.location[v] = loc;
      cut_.on_b[v] = 1;
    }
  }

  void add_exterior_vertices() {
    cut_.b_vertex_gid.assign(m_.positions.size(), kNone);
    for (std::uint32_t b = 0; b < m_.positions.size(); ++b) {
      if (m_.vf_offsets[b] == m_.vf_offsets[b + 1]) continue;  // unused by B's triangles
      if (b_owner_[b] != kNone) {
        cut_.b_vertex_gid[b] = b_owner_[b];
        continue;
      }
      const Location loc = vertex_location(m_, b);
      cut_.b_vertex_gid[b] = new_vertex(loc.point, -1 - std::int64_t(b), &loc);
    }
  }

  // The global id of an intermediate point of the trace of S edge p-q.
  std::uint32_t trace_point(const TraceStep& step, std::uint32_t p, std::uint32_t q, const std::vector<EdgeTrace>& traces) {
    const Location& loc = step.to;
    if (loc.kind == Location::kVertex) {
      if (b_owner_[loc.id] != kNone)
        throw RunError("the trace of fracture surface boundary edge " + vertex_pair(p, q) +
                       " runs through fracture surface vertex " + std::to_string(b_owner_[loc.id]));
      return cut_.b_vertex_gid[loc.id];
    }
    if (loc.kind == Location::kFace) {
      if (step.clear_of == kNone) throw RunError("the trace of boundary edge " + vertex_pair(p, q) + " stopped inside a triangle");
      const std::uint32_t id = new_vertex(loc.point, kRoutePoint, &loc);
      cut_.face_points[loc.id].push_back(id);
      out_.route_points.push_back({id, p, q, 0.0, loc.id, loc.bary, traces[step.clear_of].p, traces[step.clear_of].q});
      return id;
    }
    const std::uint32_t id = new_vertex(loc.point, kCrossing, &loc);
    cut_.edge_points[loc.id].emplace_back(loc.t, id);
    CrossingPoint c;
    c.vertex = id;
    c.s_from = p;
    c.s_to = q;
    c.b_from = m_.edges[loc.id].x;
    c.b_to = m_.edges[loc.id].y;
    c.t = loc.t;
    out_.crossings.push_back(c);
    return id;
  }

  void trace_boundary() {
    std::vector<EdgeTrace> traces;
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e) {
      if (s_.edge_special[e] != kEdgeBoundary) continue;
      const std::uint32_t f = s_.ef_faces[s_.ef_offsets[e]];
      const glm::uvec4 face = s_.faces[f];
      int k = 0;
      while (!((face[k] == s_.edges[e].x || face[k] == s_.edges[e].y) &&
               (face[(k + 1) % 3] == s_.edges[e].x || face[(k + 1) % 3] == s_.edges[e].y)))
        ++k;
      traces.push_back(trace_edge(f, k, face[k], face[(k + 1) % 3]));
    }
    out_.traces_rerouted = untangle_traces(m_, traces, options_.plane_epsilon * m_.diagonal, options_.location_epsilon);
    for (const EdgeTrace& t : traces) insert_trace(t, traces);
  }

  EdgeTrace trace_edge(std::uint32_t f, int k, std::uint32_t p, std::uint32_t q) const {
    EdgeTrace out{f, k, p, q, {}};
    // When the fan from the opposite corner c failed (a face meeting B at a slant, its trace
    // bending past c), the edge is traced in the plane through it along the face's normal: the
    // fan then sees the trace where it sees the edge.
    glm::dvec3 plane(0.0);
    if (retries_.along_normal.count(repair_.face_origin[f])) {
      const glm::dvec3 d = out_.positions[q] - out_.positions[p], c = out_.positions[s_.faces[f][(k + 2) % 3]];
      plane = glm::cross(d, glm::cross(d, c - out_.positions[p]));
    }
    try {
      out.trace = trace_on_exterior(m_, cut_.location[p], cut_.location[q], options_.plane_epsilon * m_.diagonal, plane);
    } catch (const RunError& err) {
      throw RunError("fracture surface boundary edge " + vertex_pair(p, q) + " (face " + std::to_string(repair_.face_origin[f]) + ") from " +
                     format_point(out_.positions[p]) + " to " + format_point(out_.positions[q]) +
                     " cannot be traced on the exterior: " + err.what());
    }
    return out;
  }

  // The trace's points become vertices and its segments cut edges; crossing and route points
  // learn how far along the trace they lie.
  void insert_trace(const EdgeTrace& t, const std::vector<EdgeTrace>& traces) {
    const std::uint32_t p = t.p, q = t.q;
    const std::size_t first_crossing = out_.crossings.size(), first_route = out_.route_points.size();
    std::vector<std::uint32_t> path{p};
    for (std::size_t i = 0; i + 1 < t.trace.steps.size(); ++i) path.push_back(trace_point(t.trace.steps[i], p, q, traces));
    path.push_back(q);
    std::vector<double> along(path.size(), 0.0);
    for (std::size_t i = 0; i < t.trace.steps.size(); ++i) {
      cut_.segments.push_back({path[i], path[i + 1], t.trace.steps[i].face, p, q});
      along[i + 1] = along[i] + glm::length(out_.positions[path[i + 1]] - out_.positions[path[i]]);
      mark_cut(path[i], path[i + 1], t.s_face, p, q);
    }
    auto fraction = [&](std::uint32_t vertex) {
      return along[std::size_t(std::find(path.begin(), path.end(), vertex) - path.begin())] / along.back();
    };
    for (std::size_t c = first_crossing; c < out_.crossings.size(); ++c) out_.crossings[c].along = fraction(out_.crossings[c].vertex);
    for (std::size_t r = first_route; r < out_.route_points.size(); ++r)
      out_.route_points[r].along = fraction(out_.route_points[r].vertex);
    paths_[{t.s_face, t.side}] = std::vector<std::uint32_t>(path.begin() + 1, path.end() - 1);
  }

  // A patch face using (a, b) in the winding of S face f lies in f's front piece.
  void mark_cut(std::uint32_t a, std::uint32_t b, std::uint32_t f, std::uint32_t p, std::uint32_t q) {
    const glm::ivec2 pieces = s_.face_pieces[f];
    auto [it, inserted] = cut_piece_.emplace(DirectedEdge{a, b}, CutSide{pieces.x, p, q});
    if (!inserted || !cut_piece_.emplace(DirectedEdge{b, a}, CutSide{pieces.y, p, q}).second) {
      auto other = inserted ? cut_piece_.find({b, a}) : it;
      throw RunError("the traces of fracture surface boundary edges " + vertex_pair(other->second.s_from, other->second.s_to) +
                     " and " + vertex_pair(p, q) + " overlap on the exterior between " + format_point(out_.positions[a]) +
                     " and " + format_point(out_.positions[b]) + ": the fracture surface folds over itself there");
    }
  }

  // Face f's corners with the inner trace points of its boundary sides, in its winding, and
  // their side masks (see triangulate_fracture_polygon).
  void fracture_polygon(std::uint32_t f, std::vector<std::uint32_t>& polygon, std::vector<unsigned>& mask) const {
    for (int k = 0; k < 3; ++k) {
      polygon.push_back(s_.faces[f][k]);
      mask.push_back((1u << k) | (1u << ((k + 2) % 3)) | (cut_.on_b[s_.faces[f][k]] ? kOnExterior : 0u));
      auto it = paths_.find({f, k});
      if (it == paths_.end()) continue;
      for (std::uint32_t g : it->second) polygon.push_back(g), mask.push_back((1u << k) | kOnExterior);
    }
  }

  // The vertices of face f's first boundary edge, in its winding.
  glm::uvec2 boundary_edge_of(std::uint32_t f) const {
    for (int k = 0; k < 3; ++k)
      if (s_.edge_special[s_.face_edges[3 * f + std::uint32_t(k)]] == kEdgeBoundary)
        return {s_.faces[f][k], s_.faces[f][(k + 1) % 3]};
    return {0, 0};
  }

  int boundary_sides(std::uint32_t f) const {
    int n = 0;
    for (int k = 0; k < 3; ++k) n += s_.edge_special[s_.face_edges[3 * f + std::uint32_t(k)]] == kEdgeBoundary;
    return n;
  }

  // The way face f faces, which its fracture polygon must keep; none (zero) for a needle-thin
  // face, whose own normal is noise next to the bends of its traces.
  glm::dvec3 orientation(std::uint32_t f) const {
    const glm::uvec4 t = s_.faces[f];
    const glm::dvec3 a = out_.positions[t.x], b = out_.positions[t.y], c = out_.positions[t.z];
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    return glm::length(n) < kNeedle * longest * longest ? glm::dvec3(0.0) : n;
  }

  void remesh_fracture_faces() {
    s_triangles_.resize(s_.faces.size());
    std::vector<UntriangulatedFaces::Face> failed;
    for (std::uint32_t f = 0; f < s_.faces.size(); ++f) {
      std::vector<std::uint32_t> polygon;
      std::vector<unsigned> mask;
      fracture_polygon(f, polygon, mask);
      if (polygon.size() == 3) {
        s_triangles_[f].push_back({polygon[0], polygon[1], polygon[2]});
        continue;
      }
      std::vector<glm::dvec3> xyz;
      for (std::uint32_t g : polygon) xyz.push_back(out_.positions[g]);
      const glm::uvec4 t = s_.faces[f];
      const glm::dvec3 normal = orientation(f);
      FracturePolygon result;
      try {
        result = triangulate_fracture_polygon(xyz, mask, normal, flat_on_exterior_);
      } catch (const RunError& err) {
        const std::string what = "fracture surface face " + std::to_string(repair_.face_origin[f]) + " near " +
                                 format_point(xyz[0]) + ": cannot insert the traced boundary points: " + err.what();
        const int sides = boundary_sides(f);
        if (sides != 1 && !(sides >= 2 && options_.remove_flaps)) throw RunError(what);
        failed.push_back({what, repair_.face_origin[f], sides >= 2, boundary_edge_of(f)});
        continue;
      }
      if (result.centre_added) {
        polygon.push_back(new_vertex(result.centre, kFaceCentre, nullptr));
        out_.face_centres.push_back({polygon.back(), repair_.face_origin[f], {t.x, t.y, t.z}, result.centre_weights});
      }
      for (const Tri& r : result.triangles) s_triangles_[f].push_back({polygon[r[0]], polygon[r[1]], polygon[r[2]]});
    }
    if (!failed.empty()) throw UntriangulatedFaces(std::move(failed));
  }

  // S crosses B where a fracture triangle with a corner on B pokes out of it (S hugging B, or
  // B concave under S's rim): its S vertices off B are to be pushed inward.
  void check_poking() const {
    std::vector<Tri> triangles;
    for (const auto& t : s_triangles_) triangles.insert(triangles.end(), t.begin(), t.end());
    const auto poking = poking_vertices(m_, out_.positions, triangles, cut_.on_b, out_.s_vertex_count, kPokeTolerance * m_.diagonal);
    if (poking.empty()) return;
    std::map<std::uint32_t, PokingOut::Vertex> vertices;
    for (const auto& [v, push] : poking)
      vertices[v] = {push.distance, std::numeric_limits<double>::infinity(), out_.positions[v], {}, push.direction};
    for (auto& [v, p] : vertices) {
      p.neighbours = neighbours_by_distance(v);
      p.limit = kMaxPush * (p.neighbours.empty() ? 0.0 : glm::distance(out_.positions[v], out_.positions[p.neighbours[0]]));
    }
    throw PokingOut(std::move(vertices));
  }

  std::vector<std::uint32_t> neighbours_by_distance(std::uint32_t v) const {
    std::vector<std::pair<double, std::uint32_t>> ring;
    for (std::uint32_t k = s_.vf_offsets[v]; k < s_.vf_offsets[v + 1]; ++k)
      for (int c = 0; c < 3; ++c)
        if (const std::uint32_t w = s_.faces[s_.vf_faces[k]][c]; w != v)
          ring.emplace_back(glm::length(out_.positions[v] - out_.positions[w]), w);
    std::sort(ring.begin(), ring.end());
    std::vector<std::uint32_t> out;
    for (const auto& [d, w] : ring)
      if (out.empty() || out.back() != w) out.push_back(w);
    return out;
  }

  double shortest_edge(std::uint32_t v, std::uint32_t* nearest = nullptr) const {
    double shortest = std::numeric_limits<double>::infinity();
    for (std::uint32_t k = s_.vf_offsets[v]; k < s_.vf_offsets[v + 1]; ++k)
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t w = s_.faces[s_.vf_faces[k]][c];
        const double length = glm::length(out_.positions[v] - out_.positions[w]);
        if (w == v || !(length < shortest)) continue;
        shortest = length;
        if (nearest) *nearest = w;
      }
    return shortest;
  }

  // Exact intersections the sampled poke test and the traces' checks cannot see: a fracture
  // triangle through a B triangle (its S vertices are pushed inward), or two fracture triangles
  // through each other (theirs are relaxed).
  void check_clashes() const {
    std::vector<Tri> triangles;
    for (const auto& t : s_triangles_) triangles.insert(triangles.end(), t.begin(), t.end());
    const Clashes c = find_clashes(out_.positions, triangles, b_triangles_, cut_.on_b, out_.s_vertex_count);
    if (c.pairs == 0) return;
    if (!c.poking.empty()) {
      std::map<std::uint32_t, PokingOut::Vertex> vertices;
      for (const auto& [v, direction] : c.poking) {
        const double shortest = shortest_edge(v);
        vertices[v] = {kClashPush * shortest, kMaxPush * shortest, out_.positions[v], neighbours_by_distance(v), direction};
      }
      throw PokingOut(std::move(vertices));
    }
    auto describe = [&](int k) {
      const Tri& t = c.first[std::size_t(k)];
      return std::string(c.first_is_exterior[std::size_t(k)] ? "exterior" : "fracture") + " triangle (" +
             format_point(out_.positions[t[0]]) + ", " + format_point(out_.positions[t[1]]) + ", " +
             format_point(out_.positions[t[2]]) + ")";
    };
    const std::string what = describe(0) + " and " + describe(1) + " intersect";
    if (c.folded.empty()) throw RunError("the pieces cannot be made: " + what);
    std::map<std::uint32_t, Folded::Vertex> vertices;
    for (std::uint32_t v : c.folded) {
      Folded::Vertex& p = vertices[v];
      p.at = out_.positions[v];
      p.shortest = shortest_edge(v, &p.nearest);
    }
    throw Folded(what, std::move(vertices));
  }

  // A triangle with its corners on B lies flat on it unless its centroid is inside B, deeper
  // than a thousandth of its longest edge (a triangle across a convex crease is).
  bool flat_on_exterior(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) const {
    const glm::dvec3 centroid = (a + b + c) / 3.0;
    const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    const double depth = std::sqrt(closest_point(m_.bvh, centroid).squared_distance);
    return !(depth > 1e-3 * longest && point_in_mesh(m_.bvh, centroid));
  }

  // Flood fill of the cut B across edges that are not on a trace: per triangle, the lowest
  // triangle of its patch.
  std::vector<std::uint32_t> patch_roots() const {
    std::vector<std::array<std::uint32_t, 3>> keyed;  // (min, max, face)
    for (std::uint32_t t = 0; t < b_triangles_.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = b_triangles_[t][k], b = b_triangles_[t][(k + 1) % 3];
        keyed.push_back({std::min(a, b), std::max(a, b), t});
      }
    std::sort(keyed.begin(), keyed.end());
    std::vector<std::uint32_t> parent(b_triangles_.size());
    for (std::uint32_t t = 0; t < parent.size(); ++t) parent[t] = t;
    auto find = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (std::size_t i = 0; i < keyed.size(); i += 2) {
      const auto same = [&](std::size_t j) { return j < keyed.size() && keyed[j][0] == keyed[i][0] && keyed[j][1] == keyed[i][1]; };
      if (!same(i + 1) || same(i + 2))
        throw RunError("internal: the cut exterior is not closed at edge " + vertex_pair(keyed[i][0], keyed[i][1]));
      if (cut_piece_.count({keyed[i][0], keyed[i][1]})) continue;
      const std::uint32_t ra = find(keyed[i][2]), rb = find(keyed[i + 1][2]);
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
    for (std::uint32_t t = 0; t < parent.size(); ++t) parent[t] = find(t);
    return parent;
  }

  // Each patch's piece, from the cut edges around it (which must agree).
  std::vector<int> assign_patches() const {
    const std::vector<std::uint32_t> root = patch_roots();
    std::map<std::uint32_t, int> patch_piece;
    for (std::uint32_t t = 0; t < b_triangles_.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        auto it = cut_piece_.find({b_triangles_[t][k], b_triangles_[t][(k + 1) % 3]});
        if (it == cut_piece_.end()) continue;
        auto [at, inserted] = patch_piece.emplace(root[t], it->second.piece);
        if (!inserted && at->second != it->second.piece)
          throw RunError("the part of the exterior around " + format_point(out_.positions[b_triangles_[root[t]][0]]) +
                         " borders pieces " + std::to_string(at->second) + " and " + std::to_string(it->second.piece) +
                         " along the cut: the fracture surface does not split the exterior consistently");
      }
    std::vector<int> piece(b_triangles_.size());
    for (std::uint32_t t = 0; t < b_triangles_.size(); ++t) {
      auto it = patch_piece.find(root[t]);
      if (it == patch_piece.end()) it = patch_piece.emplace(root[t], untouched_piece(b_triangles_[root[t]])).first;
      piece[t] = it->second;
    }
    return piece;
  }

  // A B component no trace touches lies in the piece on the side of the nearest S face.
  int untouched_piece(const Tri& t) const {
    const glm::dvec3 x = (out_.positions[t[0]] + out_.positions[t[1]] + out_.positions[t[2]]) / 3.0;
    double best = std::numeric_limits<double>::infinity();
    int piece = 0;
    for (std::uint32_t f = 0; f < s_.faces.size(); ++f) {
      const glm::dvec3 a = out_.positions[s_.faces[f].x], b = out_.positions[s_.faces[f].y], c = out_.positions[s_.faces[f].z];
      const ClosestPoint cp = closest_point_on_triangle(x, a, b, c);
      if (!(cp.squared_distance < best)) continue;
      best = cp.squared_distance;
      piece = glm::dot(x - cp.point, glm::cross(b - a, c - a)) >= 0.0 ? s_.face_pieces[f].x : s_.face_pieces[f].y;
    }
    return piece;
  }

  void assemble(const std::vector<int>& b_piece) {
    out_.pieces.resize(std::size_t(std::max(s_.piece_count, 1)));
    for (std::uint32_t f = 0; f < s_.faces.size(); ++f) {
      PieceSet::Piece& front = out_.pieces[std::size_t(s_.face_pieces[f].x)];
      PieceSet::Piece& back = out_.pieces[std::size_t(s_.face_pieces[f].y)];
      for (const Tri& t : s_triangles_[f]) {
        back.triangles.push_back(t);
        back.inside.push_back(1);
        front.triangles.push_back({t[0], t[2], t[1]});
        front.inside.push_back(1);
      }
    }
    for (std::uint32_t t = 0; t < b_triangles_.size(); ++t) {
      PieceSet::Piece& piece = out_.pieces[std::size_t(b_piece[t])];
      piece.triangles.push_back(b_triangles_[t]);
      piece.inside.push_back(0);
    }
  }

  const ExteriorMesh& m_;
  PieceOptions options_;
  const Retries& retries_;
  RepairReport repair_;
  FractureSurface s_;  // the input after repair_boundary
  PieceSet out_;
  ExteriorCut cut_;
  std::vector<std::uint32_t> b_owner_;                       // per B vertex: the S vertex on it
  std::map<std::pair<std::uint32_t, int>, std::vector<std::uint32_t>> paths_;  // (S face, side) -> inner trace points
  struct CutSide {
    int piece;                    // of the patch face using the directed cut edge
    std::uint32_t s_from, s_to;  // the S boundary edge traced there
  };
  std::map<DirectedEdge, CutSide> cut_piece_;
  std::vector<Tri> b_triangles_;
  std::vector<std::vector<Tri>> s_triangles_;
  const FlatTest flat_on_exterior_ = [this](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return flat_on_exterior(a, b, c);
  };
};

RunError gave_up(const Retries& retries, const std::string& last) {
  return RunError("the pieces cannot be made: still a problem after " + std::to_string(retries.attempts + 1) +
                  " attempts to repair the fracture surface's rim: " + last);
}

}  // namespace

PieceSet build_pieces(const FractureSurface& s, const MeshSoup& exterior, const PieceOptions& options) {
  const ExteriorMesh m = make_exterior_mesh(exterior);
  const FractureSurface input = checked(s);
  Retries retries;
  std::optional<RepairedInput> repaired;
  for (;; ++retries.attempts) {
    try {
      if (!repaired || !repaired->made_for(retries)) repaired = repair_input(input, m, options, retries);
      PieceSet out = PieceBuilder(*repaired, m, options, retries).run();
      out.attempts = std::uint32_t(retries.attempts + 1);
      return out;
    } catch (const PokingOut& poking) {
      std::string why;
      if (!retries.next(poking, why)) throw RunError(why);
      if (retries.attempts >= kMaxAttempts) throw gave_up(retries, poking.describe());
    } catch (const TracesCross& crossed) {
      if (!retries.next(crossed, double_positions(input))) throw RunError(crossed.what());
      if (retries.attempts >= kMaxAttempts) throw gave_up(retries, crossed.what());
    } catch (const Folded& folded) {
      std::string why;
      if (!retries.next(folded, why)) throw RunError(why);
      if (retries.attempts >= kMaxAttempts) throw gave_up(retries, folded.what());
    } catch (const UntriangulatedFaces& failed) {
      std::string why = failed.what();
      if (!retries.next(failed, why)) throw RunError(why);
      if (retries.attempts >= kMaxAttempts) throw gave_up(retries, failed.what());
    }
  }
}

}  // namespace fracref
