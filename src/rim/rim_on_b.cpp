// embed_rim: locate, trace, split (rim/rim_on_b.hpp).
#include "rim/rim_on_b.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "geom/bvh.hpp"
#include "geom/predicates.hpp"

#include "rim/rim_clip.hpp"
#include "util/error.hpp"

namespace fracref::rim {
namespace {

// A rim vertex's inner edge is probed at this fraction of its length, and followed at most this
// far to where it enters B.
constexpr double kRimProbe = 0.005;
constexpr double kMaxRetract = 0.3;

std::string pair_name(std::uint32_t a, std::uint32_t b) { return std::to_string(a) + "-" + std::to_string(b); }

glm::dvec3 at(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }

class Embedder {
 public:
  Embedder(FractureSurface& s, const ExteriorMesh& m, const EmbedOptions& o) : s_(s), m_(m), o_(o) {}

  Embedding run() {
    locate_rim();
    out_.clipped = clip_grazing_rim(s_, m_, out_.rim, out_.added, o_);
    rebuild_adjacency(s_);
    std::map<std::uint32_t, std::array<std::vector<std::uint32_t>, 3>> sides;  // face -> points per side
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e) {
      if (s_.edge_special[e] != kEdgeBoundary) continue;
      const std::uint32_t f = s_.ef_faces[s_.ef_offsets[e]];
      const int k = side_of(f, s_.edges[e]);
      const std::uint32_t p = s_.faces[f][k], q = s_.faces[f][(k + 1) % 3];
      if (common_face(m_, out_.rim.at[p], out_.rim.at[q]) != kNone) continue;
      sides[f][std::size_t(k)] = trace_edge(p, q);
    }
    for (const auto& [f, points] : sides) split_face(f, points);
    rebuild_adjacency(s_);
    return std::move(out_);
  }

 private:
  int side_of(std::uint32_t f, glm::uvec2 edge) const {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = s_.faces[f][k], b = s_.faces[f][(k + 1) % 3];
      if ((a == edge.x && b == edge.y) || (a == edge.y && b == edge.x)) return k;
    }
    throw RunError("internal: fracture surface face " + std::to_string(f) + " does not hold its edge " + pair_name(edge.x, edge.y));
  }

  // Where S overshoots a concave B, a rim vertex's inner edge leaves it outside B, and its faces
  // would cross B next to the rim: the vertex is moved along that edge to where the edge enters
  // B (the farthest such point over its inner edges, at most kMaxRetract along), unless that
  // turns one of its faces over.
  void retract_overshooting_rim() {
    const double tolerance = 1e-7 * m_.diagonal;
    for (std::uint32_t w = 0; w < s_.positions.size(); ++w) {
      if (!(s_.vertex_flags[w] & kVertexBoundary)) continue;
      double along = 0.0;
      std::uint32_t toward = w;
      for (std::uint32_t k = s_.vf_offsets[w]; k < s_.vf_offsets[w + 1]; ++k)
        for (int c = 0; c < 3; ++c) {
          const std::uint32_t v = s_.faces[s_.vf_faces[k]][c];
          if (v == w || (s_.vertex_flags[v] & kVertexBoundary)) continue;
          const double t = entry_along(at(s_, w), at(s_, v), tolerance);
          if (t > along) along = t, toward = v;
        }
      if (along > 0.0) move_rim_vertex(w, closest_point(m_.bvh, at(s_, w) + along * (at(s_, toward) - at(s_, w))).point);
    }
  }

  // Whether every vertex off the rim of a face at rim vertex w lies strictly inside B's side of
  // the plane of each triangle of B that holds w's location (the contact rule of
  // refine/exterior_contact.hpp), with w at `x`; and (the worst offender) the one rising most.
  bool faces_inside_holders(std::uint32_t w, const glm::dvec3& x, std::uint32_t* worst) const {
    const Location loc = locate_on_exterior(m_, x, o_.location_epsilon, nullptr);
    bool ok = true;
    double most = -1.0;
    for (std::uint32_t k = s_.vf_offsets[w]; k < s_.vf_offsets[w + 1]; ++k)
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = s_.faces[s_.vf_faces[k]][c];
        if (v == w || (s_.vertex_flags[v] & kVertexBoundary)) continue;
        for (std::uint32_t h : location_faces(m_, loc)) {
          const auto& t = m_.triangles[h];
          if (orient3d(m_.positions[t[0]], m_.positions[t[1]], m_.positions[t[2]], at(s_, v)) > 0) continue;
          ok = false;
          const double rise = glm::dot(at(s_, v) - x, m_.face_normals[h]) / std::max(1e-300, glm::length(at(s_, v) - x));
          if (rise > most) most = rise, *worst = v;
        }
      }
    return ok;
  }

  // Where S meets B at a grazing angle, a face at a rim vertex rises above B's tangent plane:
  // the rim vertex is moved toward that face's offending vertex, onto B, the least of a few
  // steps that makes every face at it start inside B (or not at all).
  void retract_grazing_rim() {
    for (std::uint32_t w = 0; w < s_.positions.size(); ++w) {
      if (!(s_.vertex_flags[w] & kVertexBoundary)) continue;
      std::uint32_t worst = w;
      if (faces_inside_holders(w, at(s_, w), &worst)) continue;
      for (double f = 0.05; f <= 0.5; f += 0.05) {
        const glm::dvec3 x = closest_point(m_.bvh, at(s_, w) + f * (at(s_, worst) - at(s_, w))).point;
        std::uint32_t unused = w;
        if (!faces_inside_holders(w, x, &unused)) continue;
        move_rim_vertex(w, x);
        break;
      }
    }
  }

  bool outside(const glm::dvec3& x, double tolerance) const {
    return std::sqrt(closest_point(m_.bvh, x).squared_distance) > tolerance && !point_in_mesh(m_.bvh, x);
  }

  // How far along the inner edge from rim vertex w to v (a fraction) it enters B, when it leaves
  // w outside B; 0 when it leaves w inside, or stays outside beyond kMaxRetract.
  double entry_along(const glm::dvec3& w, const glm::dvec3& v, double tolerance) const {
    if (!outside(w + kRimProbe * (v - w), tolerance)) return 0.0;
    double out = kRimProbe, in = -1.0;
    for (double t = 2.0 * kRimProbe; t <= kMaxRetract; t += kRimProbe) {
      if (!outside(w + t * (v - w), tolerance)) {
        in = t;
        break;
      }
      out = t;
    }
    if (in < 0.0) return 0.0;
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (out + in);
      (outside(w + mid * (v - w), tolerance) ? out : in) = mid;
    }
    return in;
  }

  void move_rim_vertex(std::uint32_t w, const glm::dvec3& to) {
    const glm::vec4 old = s_.positions[w];
    std::vector<glm::dvec3> normals;
    for (std::uint32_t k = s_.vf_offsets[w]; k < s_.vf_offsets[w + 1]; ++k) normals.push_back(face_normal(s_.vf_faces[k]));
    s_.positions[w] = glm::vec4(glm::vec3(to), 1.0f);
    for (std::uint32_t k = s_.vf_offsets[w]; k < s_.vf_offsets[w + 1]; ++k)
      if (!(glm::dot(face_normal(s_.vf_faces[k]), normals[k - s_.vf_offsets[w]]) > 0.0)) {
        s_.positions[w] = old;
        return;
      }
    ++out_.retracted;
  }

  glm::dvec3 face_normal(std::uint32_t f) const {
    const glm::uvec4 t = s_.faces[f];
    return glm::cross(at(s_, t.y) - at(s_, t.x), at(s_, t.z) - at(s_, t.x));
  }

  void locate_rim() {
    out_.rim.at.assign(s_.positions.size(), Location{});
    out_.rim.on_b.assign(s_.positions.size(), 0);
    const double tolerance = o_.snap_tolerance * m_.diagonal;
    for (std::uint32_t v = 0; v < s_.positions.size(); ++v) {
      if (!(s_.vertex_flags[v] & kVertexBoundary)) continue;
      double distance = 0.0;
      const Location loc = locate_on_exterior(m_, at(s_, v), o_.location_epsilon, &distance);
      if (!(distance <= tolerance))
        throw RunError("fracture surface boundary vertex " + std::to_string(v) + " at " + format_point(at(s_, v)) + " is " +
                       std::to_string(distance) + " from the exterior (tolerance " + std::to_string(tolerance) +
                       "): the fracture surface must end on the exterior");
      if (loc.kind == Location::kVertex) claim(loc.id, v);
      out_.rim.at[v] = loc;
      out_.rim.on_b[v] = 1;
      s_.positions[v] = glm::vec4(glm::vec3(loc.point), 1.0f);
    }
  }

  void claim(std::uint32_t b, std::uint32_t v) {
    auto [it, inserted] = b_owner_.emplace(b, v);
    if (!inserted)
      throw RunError("fracture surface vertices " + std::to_string(it->second) + " and " + std::to_string(v) +
                     " both lie on exterior vertex " + std::to_string(b) + " at " + format_point(m_.positions[b]));
  }

  // The trace's inner points, new vertices of S on the chord's fraction of the trace's length.
  std::vector<std::uint32_t> trace_edge(std::uint32_t p, std::uint32_t q) {
    Trace trace;
    try {
      trace = trace_on_exterior(m_, out_.rim.at[p], out_.rim.at[q], o_.plane_epsilon * m_.diagonal);
    } catch (const RunError& err) {
      throw RunError("fracture surface boundary edge " + pair_name(p, q) + " from " + format_point(at(s_, p)) + " to " +
                     format_point(at(s_, q)) + " cannot be traced on the exterior: " + err.what());
    }
    std::vector<double> along{0.0};
    glm::dvec3 last = out_.rim.at[p].point;
    for (const TraceStep& step : trace.steps) along.push_back(along.back() + glm::length(step.to.point - last)), last = step.to.point;
    std::vector<std::uint32_t> points;
    for (std::size_t i = 0; i + 1 < trace.steps.size(); ++i) {
      const Location& loc = trace.steps[i].to;
      if (loc.kind == Location::kFace)
        throw RunError("internal: the trace of fracture surface boundary edge " + pair_name(p, q) + " stopped inside a triangle");
      const std::uint32_t v = std::uint32_t(s_.positions.size());
      if (loc.kind == Location::kVertex) claim(loc.id, v);
      const double t = along.back() > 0.0 ? along[i + 1] / along.back() : 0.5;
      s_.positions.push_back(glm::vec4(glm::vec3(loc.point), 1.0f));
      out_.rim.at.push_back(loc);
      out_.rim.on_b.push_back(1);
      out_.added.push_back({v, {p, q, q}, glm::dvec3(1.0 - t, t, 0.0)});
      points.push_back(v);
    }
    return points;
  }

  // Face f with the traced points of its sides: a fan from the corner opposite its one traced
  // side, or from its centroid.
  void split_face(std::uint32_t f, const std::array<std::vector<std::uint32_t>, 3>& sides) {
    const glm::uvec4 face = s_.faces[f];
    std::vector<std::uint32_t> polygon;
    int traced = 0, only = 0;
    for (int k = 0; k < 3; ++k) {
      polygon.push_back(face[k]);
      polygon.insert(polygon.end(), sides[std::size_t(k)].begin(), sides[std::size_t(k)].end());
      if (!sides[std::size_t(k)].empty()) ++traced, only = k;
    }
    std::uint32_t apex = face[(only + 2) % 3];
    if (traced > 1) {
      apex = std::uint32_t(s_.positions.size());
      s_.positions.push_back(glm::vec4((glm::vec3(s_.positions[face.x]) + glm::vec3(s_.positions[face.y]) + glm::vec3(s_.positions[face.z])) / 3.0f, 1.0f));
      out_.rim.at.push_back(Location{});
      out_.rim.on_b.push_back(0);
      out_.added.push_back({apex, {face.x, face.y, face.z}, glm::dvec3(1.0 / 3.0)});
    }
    bool first = true;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const std::uint32_t a = polygon[i], b = polygon[(i + 1) % polygon.size()];
      if (a == apex || b == apex) continue;
      const glm::uvec4 t(a, b, apex, 0u);
      if (first) s_.faces[f] = t, first = false;
      else s_.faces.push_back(t), s_.face_pieces.push_back(s_.face_pieces[f]);
    }
  }

  FractureSurface& s_;
  const ExteriorMesh& m_;
  EmbedOptions o_;
  Embedding out_;
  std::map<std::uint32_t, std::uint32_t> b_owner_;  // B vertex -> the S vertex on it
};

}  // namespace

Embedding embed_rim(FractureSurface& s, const ExteriorMesh& m, const EmbedOptions& options) {
  return Embedder(s, m, options).run();
}

Location split_location(const ExteriorMesh& m, const RimOnB& rim, std::uint32_t a, std::uint32_t b, double t) {
  return location_between(m, rim.at[a], rim.at[b], t);
}

std::string find_unembedded_rim(const FractureSurface& s, const ExteriorMesh& m, const RimOnB& rim) {
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    if (s.edge_special[e] != kEdgeBoundary) continue;
    const glm::uvec2 ab = s.edges[e];
    for (std::uint32_t v : {ab.x, ab.y})
      if (v >= rim.on_b.size() || !rim.on_b[v]) return "fracture surface rim vertex " + std::to_string(v) + " has no location on the exterior";
    if (common_face(m, rim.at[ab.x], rim.at[ab.y]) == kNone)
      return "fracture surface rim edge " + pair_name(ab.x, ab.y) + " does not lie in one triangle of the exterior";
  }
  return "";
}

}  // namespace fracref::rim
