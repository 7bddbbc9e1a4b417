// embed_rim: locate, trace, split (rim/rim_on_b.hpp).
#include "rim/rim_on_b.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "geom/bvh.hpp"
#include "geom/predicates.hpp"

#include "rim/trim_to_exterior.hpp"
#include "util/error.hpp"

namespace fracref::rim {
namespace {

std::string pair_name(std::uint32_t a, std::uint32_t b) { return std::to_string(a) + "-" + std::to_string(b); }

glm::dvec3 at(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }

class Embedder {
 public:
  Embedder(FractureSurface& s, const ExteriorMesh& m, const EmbedOptions& o) : s_(s), m_(m), o_(o) {}

  Embedding run() {
    locate_rim();
    split_unembedded();
    out_.trim = trim_to_exterior(s_, m_, out_.rim, out_.added);
    // A face the trim dropped because it lies on B (a flap) leaves its edge to the rest of S as a
    // new rim edge, which may cross B's edges: split there too.
    if (!find_unembedded_rim(s_, m_, out_.rim).empty()) split_unembedded();
    return std::move(out_);
  }

 private:
  // Every rim edge whose ends share no triangle of B split where its trace crosses B's edges.
  void split_unembedded() {
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
  }

  int side_of(std::uint32_t f, glm::uvec2 edge) const {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = s_.faces[f][k], b = s_.faces[f][(k + 1) % 3];
      if ((a == edge.x && b == edge.y) || (a == edge.y && b == edge.x)) return k;
    }
    throw RunError("internal: fracture surface face " + std::to_string(f) + " does not hold its edge " + pair_name(edge.x, edge.y));
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
