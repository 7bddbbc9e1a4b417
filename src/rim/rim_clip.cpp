// clip_grazing_rim (rim/rim_clip.hpp).
#include "rim/rim_clip.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "geom/bvh.hpp"
#include "geom/predicates.hpp"
#include "io/polygon_triangulation.hpp"
#include "util/error.hpp"

namespace fracref::rim {
namespace {

glm::dvec3 at(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }

// Where segment c -> e first meets B going from c: the location and the fraction along.
bool first_crossing(const ExteriorMesh& m, const glm::dvec3& c, const glm::dvec3& e, double epsilon, Location& out,
                    double& along) {
  Aabb box;
  box.expand(c);
  box.expand(e);
  std::vector<std::uint32_t> near;
  query_box(m.bvh, box, near);
  double best = std::numeric_limits<double>::infinity();
  std::uint32_t face = kNone;
  glm::dvec3 weights(0.0);
  const glm::dvec3 d = e - c;
  for (std::uint32_t t : near) {  // Moller-Trumbore
    const auto& tri = m.triangles[t];
    const glm::dvec3 a = m.positions[tri[0]], e1 = m.positions[tri[1]] - a, e2 = m.positions[tri[2]] - a;
    const glm::dvec3 p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-300) continue;
    const glm::dvec3 tv = c - a;
    const double u = glm::dot(tv, p) / det;
    const glm::dvec3 q = glm::cross(tv, e1);
    const double v = glm::dot(d, q) / det, s = glm::dot(e2, q) / det;
    if (u < -1e-12 || v < -1e-12 || u + v > 1.0 + 1e-12 || s < 0.0 || s > 1.0 || !(s < best)) continue;
    best = s, face = t, weights = {1.0 - u - v, u, v};
  }
  if (face == kNone) return false;
  weights = glm::max(weights, glm::dvec3(0.0));
  for (int k = 0; k < 3; ++k)
    if (weights[k] < epsilon) weights[k] = 0.0;
  out = location_from_weights(m, face, weights / (weights.x + weights.y + weights.z));
  along = best;
  return true;
}

class Clipper {
 public:
  Clipper(FractureSurface& s, const ExteriorMesh& m, RimOnB& rim, std::vector<EmbeddedVertex>& added, const EmbedOptions& o)
      : s_(s), m_(m), rim_(rim), added_(added), o_(o) {}

  std::uint32_t run() {
    bad_.assign(s_.positions.size(), 0);
    for (std::uint32_t v = 0; v < s_.positions.size(); ++v) bad_[v] = on_rim(v) && grazing(v);
    std::vector<std::uint32_t> faces;
    for (std::uint32_t f = 0; f < s_.faces.size(); ++f)
      if (bad_[s_.faces[f].x] || bad_[s_.faces[f].y] || bad_[s_.faces[f].z]) faces.push_back(f);
    std::vector<char> kept(s_.positions.size(), 0);  // a bad vertex still used by a face left as it was
    for (std::uint32_t f : faces)
      if (!clip_face(f))
        for (int k = 0; k < 3; ++k) kept[s_.faces[f][k]] = 1;
    std::uint32_t clipped = 0;
    for (std::uint32_t v = 0; v < bad_.size(); ++v)
      if (bad_[v] && !kept[v]) rim_.on_b[v] = 0, ++clipped;
    return clipped;
  }

 private:
  enum Kind { kIn, kOn, kOut };
  bool on_rim(std::uint32_t v) const { return v < rim_.on_b.size() && rim_.on_b[v]; }
  Kind kind(std::uint32_t v) const { return v < bad_.size() && bad_[v] ? kOut : (on_rim(v) ? kOn : kIn); }

  bool grazing(std::uint32_t p) const {
    const std::vector<std::uint32_t> holders = location_faces(m_, rim_.at[p]);
    for (std::uint32_t k = s_.vf_offsets[p]; k < s_.vf_offsets[p + 1]; ++k)
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = s_.faces[s_.vf_faces[k]][c];
        if (v == p || on_rim(v)) continue;
        for (std::uint32_t h : holders) {
          const auto& t = m_.triangles[h];
          if (orient3d(m_.positions[t[0]], m_.positions[t[1]], m_.positions[t[2]], at(s_, v)) <= 0) return true;
        }
      }
    return false;
  }

  std::uint32_t new_rim_vertex(const Location& loc, const std::array<std::uint32_t, 3>& parents, const glm::dvec3& w) {
    const std::uint32_t id = std::uint32_t(s_.positions.size());
    s_.positions.push_back(glm::vec4(glm::vec3(loc.point), 1.0f));
    rim_.at.push_back(loc);
    rim_.on_b.push_back(1);
    added_.push_back({id, parents, w});
    return id;
  }

  // The point where edge in -> out (an inside corner to a grazing rim vertex) enters B, shared by
  // the faces on the edge; kNone when the edge never meets B.
  std::uint32_t entry(std::uint32_t in, std::uint32_t out) {
    const auto key = std::make_pair(std::min(in, out), std::max(in, out));
    if (auto it = entries_.find(key); it != entries_.end()) return it->second;
    const glm::dvec3 c = at(s_, in), p = rim_.at[out].point;
    const double lift = 0.05 * glm::length(p - c);
    Location loc;
    double along = 0.0;
    std::uint32_t id = kNone;
    if (first_crossing(m_, c, p + lift * location_normal(m_, rim_.at[out]), o_.location_epsilon, loc, along))
      id = new_rim_vertex(loc, {in, out, out}, glm::dvec3(1.0 - std::min(along, 1.0), std::min(along, 1.0), 0.0));
    entries_[key] = id;
    return id;
  }

  // Weights of x on face f's corners (x near its plane).
  glm::dvec3 face_weights(const glm::uvec4& f, const glm::dvec3& x) const {
    const glm::dvec3 a = at(s_, f.x), b = at(s_, f.y), c = at(s_, f.z);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double n2 = glm::dot(n, n);
    if (!(n2 > 0.0)) return glm::dvec3(1.0 / 3.0);
    const double wb = glm::dot(glm::cross(x - a, c - a), n) / n2, wc = glm::dot(glm::cross(b - a, x - a), n) / n2;
    return {1.0 - wb - wc, wb, wc};
  }

  bool clip_face(std::uint32_t f) {
    glm::uvec4 face = s_.faces[f];
    int start = 0;
    while (start < 3 && kind(face[start]) != kIn) ++start;
    if (start == 3) return false;
    const std::uint32_t v0 = face[start], v1 = face[(start + 1) % 3], v2 = face[(start + 2) % 3];
    const std::uint32_t corner[3] = {v0, v1, v2};
    std::vector<std::uint32_t> items;
    std::vector<char> traced;  // per item: B lies between the previous item and it
    bool pending = false;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = corner[k], w = corner[(k + 1) % 3];
      if (kind(v) != kOut) items.push_back(v), traced.push_back(pending), pending = false;
      else pending = true;
      if ((kind(v) == kIn && kind(w) == kOut) || (kind(v) == kOut && kind(w) == kIn)) {
        const std::uint32_t x = kind(v) == kIn ? entry(v, w) : entry(w, v);
        if (x == kNone) return false;
        items.push_back(x), traced.push_back(pending), pending = false;
      }
    }
    if (pending) traced[0] = 1;
    const glm::dvec3 normal = glm::cross(at(s_, face.y) - at(s_, face.x), at(s_, face.z) - at(s_, face.x));
    std::vector<std::uint32_t> polygon;
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (traced[i]) {
        const std::uint32_t from = items[(i + items.size() - 1) % items.size()], to = items[i];
        if (!on_rim(from) || !on_rim(to)) return false;
        try {
          const Trace trace = trace_on_exterior(m_, rim_.at[from], rim_.at[to], o_.plane_epsilon * m_.diagonal, normal);
          for (std::size_t k = 0; k + 1 < trace.steps.size(); ++k) {
            const Location& loc = trace.steps[k].to;
            const glm::dvec3 w = face_weights(face, loc.point);
            polygon.push_back(new_rim_vertex(loc, {face.x, face.y, face.z}, w));
          }
        } catch (const RunError&) {
          // ends on one point of B, or no walk: the cut points are joined directly
        }
      }
      polygon.push_back(items[i]);
    }
    std::vector<glm::dvec3> points;
    for (std::uint32_t v : polygon) points.push_back(on_rim(v) ? rim_.at[v].point : at(s_, v));
    std::vector<std::uint32_t> local(polygon.size());
    for (std::uint32_t i = 0; i < local.size(); ++i) local[i] = i;
    std::vector<std::array<std::uint32_t, 3>> tris;
    triangulate_polygon(points, local.data(), local.size(), tris);
    bool first = true;
    for (const auto& t : tris) {
      const glm::uvec4 g(polygon[t[0]], polygon[t[1]], polygon[t[2]], 0u);
      if (first) s_.faces[f] = g, first = false;
      else s_.faces.push_back(g), s_.face_pieces.push_back(s_.face_pieces[f]);
    }
    return true;
  }

  FractureSurface& s_;
  const ExteriorMesh& m_;
  RimOnB& rim_;
  std::vector<EmbeddedVertex>& added_;
  EmbedOptions o_;
  std::vector<char> bad_;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> entries_;
};

}  // namespace

std::uint32_t clip_grazing_rim(FractureSurface& s, const ExteriorMesh& m, RimOnB& rim, std::vector<EmbeddedVertex>& added,
                               const EmbedOptions& options) {
  return Clipper(s, m, rim, added, options).run();
}

}  // namespace fracref::rim
