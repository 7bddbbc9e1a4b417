// B's flat adjacency and points located on B.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "geom/intersect.hpp"
#include "geom/angles.hpp"
#include "geom/predicates.hpp"
#include "rim/exterior_mesh.hpp"
#include "util/error.hpp"

namespace fracref::rim {
namespace {

struct DirectedEdge {
  std::uint32_t a, b, face, side;
};

std::string edge_name(std::uint32_t a, std::uint32_t b) { return std::to_string(a) + "-" + std::to_string(b); }

void check_soup(const MeshSoup& soup) {
  if (soup.triangles.empty()) throw InputError("exterior: no triangles");
  for (std::size_t v = 0; v < soup.positions.size(); ++v) {
    const glm::dvec3& p = soup.positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError("exterior: vertex " + std::to_string(v) + " has a non-finite coordinate");
  }
  for (std::size_t f = 0; f < soup.triangles.size(); ++f) {
    const auto& t = soup.triangles[f];
    for (std::uint32_t i : t)
      if (i >= soup.positions.size())
        throw InputError("exterior: face " + std::to_string(f) + " has vertex " + std::to_string(i) + " out of range (" +
                         std::to_string(soup.positions.size()) + " vertices)");
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
      throw InputError("exterior: face " + std::to_string(f) + " repeats a vertex");
  }
}

// Every undirected edge must have exactly two faces using it in opposite directions: B is the
// closed, consistently wound boundary of a solid.
void build_edges(ExteriorMesh& m) {
  std::vector<DirectedEdge> half;
  half.reserve(3 * m.triangles.size());
  for (std::uint32_t f = 0; f < m.triangles.size(); ++f)
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t a = m.triangles[f][k], b = m.triangles[f][(k + 1) % 3];
      half.push_back({std::min(a, b), std::max(a, b), f, k});
    }
  std::sort(half.begin(), half.end(), [](const DirectedEdge& x, const DirectedEdge& y) {
    return std::tie(x.a, x.b, x.face) < std::tie(y.a, y.b, y.face);
  });
  m.face_edges.assign(m.triangles.size(), {kNone, kNone, kNone});
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i;
    while (j < half.size() && half[j].a == half[i].a && half[j].b == half[i].b) ++j;
    if (j - i != 2)
      throw InputError("exterior: edge " + edge_name(half[i].a, half[i].b) + " has " + std::to_string(j - i) +
                       " faces (the exterior must be closed and manifold: exactly 2 per edge)");
    const auto& f0 = m.triangles[half[i].face];
    const auto& f1 = m.triangles[half[i + 1].face];
    if (f0[half[i].side] == f1[half[i + 1].side])
      throw InputError("exterior: faces " + std::to_string(half[i].face) + " and " + std::to_string(half[i + 1].face) +
                       " use edge " + edge_name(half[i].a, half[i].b) + " in the same direction (inconsistent winding)");
    const std::uint32_t e = std::uint32_t(m.edges.size());
    m.edges.emplace_back(half[i].a, half[i].b);
    m.edge_faces.push_back({half[i].face, half[i + 1].face});
    m.face_edges[half[i].face][half[i].side] = e;
    m.face_edges[half[i + 1].face][half[i + 1].side] = e;
    i = j;
  }
}

void build_vertex_faces(ExteriorMesh& m) {
  m.vf_offsets.assign(m.positions.size() + 1, 0);
  for (const auto& t : m.triangles)
    for (std::uint32_t v : t) ++m.vf_offsets[v + 1];
  for (std::size_t v = 0; v < m.positions.size(); ++v) m.vf_offsets[v + 1] += m.vf_offsets[v];
  m.vf_faces.resize(m.vf_offsets.back());
  std::vector<std::uint32_t> fill(m.vf_offsets.begin(), m.vf_offsets.end() - 1);
  for (std::uint32_t f = 0; f < m.triangles.size(); ++f)
    for (std::uint32_t v : m.triangles[f]) m.vf_faces[fill[v]++] = f;
}

// Points of side 1 (corner 1 at (1, 0) to corner 2 at (0, 1)) get x + y == 1 exactly: the
// coordinate >= 0.5 is computed from the other by an exact subtraction (Sterbenz).
glm::dvec2 diagonal_from_y(double y) {
  if (y >= 0.5) return {1.0 - y, y};
  const double x = 1.0 - y;
  return {x, 1.0 - x};
}
glm::dvec2 diagonal_from_x(double x) {
  const glm::dvec2 p = diagonal_from_y(x);
  return {p.y, p.x};
}

}  // namespace

ExteriorMesh make_exterior_mesh(const MeshSoup& soup) {
  check_soup(soup);
  ExteriorMesh m;
  m.positions = soup.positions;
  m.triangles = soup.triangles;
  build_edges(m);
  build_vertex_faces(m);
  m.face_normals.resize(m.triangles.size());
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const auto& t = m.triangles[f];
    const glm::dvec3 n = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
    const double len = glm::length(n);
    m.face_normals[f] = len > 0.0 ? n / len : glm::dvec3(0.0);
  }
  double volume = 0.0;
  for (const auto& t : m.triangles)
    volume += glm::dot(m.positions[t[0]], glm::cross(m.positions[t[1]], m.positions[t[2]]));
  if (!(volume > 0.0))
    throw InputError("exterior: the surface is wound inward (volume " + std::to_string(volume / 6.0) +
                     "): faces must run counterclockwise seen from outside");
  m.bvh = build_bvh(m.positions, m.triangles);
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const auto& t : m.triangles)
    for (std::uint32_t v : t) {
      lo = glm::min(lo, m.positions[v]);
      hi = glm::max(hi, m.positions[v]);
    }
  m.diagonal = glm::length(hi - lo);
  return m;
}

std::uint32_t find_exterior_edge(const ExteriorMesh& m, std::uint32_t a, std::uint32_t b) {
  const glm::uvec2 key(std::min(a, b), std::max(a, b));
  auto it = std::lower_bound(m.edges.begin(), m.edges.end(), key,
                             [](const glm::uvec2& x, const glm::uvec2& y) { return x.x < y.x || (x.x == y.x && x.y < y.y); });
  return (it != m.edges.end() && *it == key) ? std::uint32_t(it - m.edges.begin()) : kNone;
}

bool same_location(const Location& a, const Location& b) {
  if (a.kind != b.kind || a.id != b.id) return false;
  if (a.kind == Location::kEdge) return a.t == b.t;
  if (a.kind == Location::kFace) return a.bary == b.bary;
  return true;
}

unsigned location_sides(const ExteriorMesh& m, const Location& loc, std::uint32_t f) {
  unsigned mask = 0;
  for (unsigned k = 0; k < 3; ++k) {
    if (loc.kind == Location::kVertex) {
      const auto& t = m.triangles[f];
      if (t[k] == loc.id || t[(k + 1) % 3] == loc.id) mask |= 1u << k;
    } else if (loc.kind == Location::kEdge && m.face_edges[f][k] == loc.id) {
      mask |= 1u << k;
    }
  }
  return mask;
}

bool location_in_face(const ExteriorMesh& m, const Location& loc, std::uint32_t f) {
  if (loc.kind == Location::kFace) return loc.id == f;
  return location_sides(m, loc, f) != 0;
}

std::vector<std::uint32_t> location_faces(const ExteriorMesh& m, const Location& loc) {
  if (loc.kind == Location::kFace) return {loc.id};
  if (loc.kind == Location::kEdge) {
    auto f = m.edge_faces[loc.id];
    if (f[0] > f[1]) std::swap(f[0], f[1]);
    return {f[0], f[1]};
  }
  return {m.vf_faces.begin() + m.vf_offsets[loc.id], m.vf_faces.begin() + m.vf_offsets[loc.id + 1]};
}

glm::dvec3 location_normal(const ExteriorMesh& m, const Location& loc) {
  glm::dvec3 n(0.0);
  if (loc.kind == Location::kFace) {
    n = m.face_normals[loc.id];
  } else if (loc.kind == Location::kEdge) {
    n = m.face_normals[m.edge_faces[loc.id][0]] + m.face_normals[m.edge_faces[loc.id][1]];
  } else {
    for (std::uint32_t f : location_faces(m, loc)) {
      const auto& t = m.triangles[f];
      const int k = t[0] == loc.id ? 0 : (t[1] == loc.id ? 1 : 2);
      const double angle = corner_angle(m.positions[t[k]], m.positions[t[(k + 1) % 3]], m.positions[t[(k + 2) % 3]]);
      n += angle * m.face_normals[f];
    }
  }
  const double len = glm::length(n);
  return len > 0.0 ? n / len : n;
}

Location vertex_location(const ExteriorMesh& m, std::uint32_t v) {
  Location loc;
  loc.kind = Location::kVertex;
  loc.id = v;
  loc.point = m.positions[v];
  return loc;
}

Location edge_location(const ExteriorMesh& m, std::uint32_t e, double t) {
  Location loc;
  loc.kind = Location::kEdge;
  loc.id = e;
  loc.t = t;
  const glm::dvec3 a = m.positions[m.edges[e].x], b = m.positions[m.edges[e].y];
  loc.point = a + t * (b - a);
  return loc;
}

Location locate_on_exterior(const ExteriorMesh& m, const glm::dvec3& p, double epsilon, double* distance) {
  const ClosestPoint cp = closest_point(m.bvh, p);
  if (distance) *distance = std::sqrt(cp.squared_distance);
  const auto& t = m.triangles[cp.triangle];
  glm::dvec3 w = glm::max(cp.barycentric, glm::dvec3(0.0));
  int zeros = 0;
  for (int k = 0; k < 3; ++k)
    if (w[k] < epsilon) w[k] = 0.0, ++zeros;
  if (zeros >= 2 || w.x + w.y + w.z <= 0.0) {
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if (w[i] > w[k]) k = i;
    return vertex_location(m, t[k]);
  }
  if (zeros == 1) {
    const int k = w[0] == 0.0 ? 1 : (w[1] == 0.0 ? 2 : 0);  // side k runs from corner k to k+1
    const std::uint32_t e = m.face_edges[cp.triangle][k];
    const double wa = w[k], wb = w[(k + 1) % 3];
    // t measured from the edge's lower vertex.
    const double toward_b = wb / (wa + wb);
    return edge_location(m, e, m.edges[e].x == t[k] ? toward_b : wa / (wa + wb));
  }
  w /= (w.x + w.y + w.z);
  Location loc;
  loc.kind = Location::kFace;
  loc.id = cp.triangle;
  loc.bary = w;
  loc.point = w.x * m.positions[t[0]] + w.y * m.positions[t[1]] + w.z * m.positions[t[2]];
  return loc;
}

glm::dvec2 side_uv(int k, bool forward, double t) {
  if (k == 0) return {forward ? t : 1.0 - t, 0.0};
  if (k == 1) return forward ? diagonal_from_y(t) : diagonal_from_x(t);
  return {0.0, forward ? 1.0 - t : t};
}

glm::dvec2 location_uv(const ExteriorMesh& m, const Location& loc, std::uint32_t f) {
  static const glm::dvec2 corners[3] = {{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}};
  const auto& t = m.triangles[f];
  if (loc.kind == Location::kFace) return {loc.bary.y, loc.bary.z};
  for (int k = 0; k < 3; ++k) {
    if (loc.kind == Location::kVertex && t[k] == loc.id) return corners[k];
    if (loc.kind == Location::kEdge && m.face_edges[f][k] == loc.id) return side_uv(k, m.edges[loc.id].x == t[k], loc.t);
  }
  return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
}

glm::dvec3 location_weights(const ExteriorMesh& m, const Location& loc, std::uint32_t f) {
  const auto& t = m.triangles[f];
  glm::dvec3 w(0.0);
  if (loc.kind == Location::kFace) return loc.bary;
  for (int k = 0; k < 3; ++k) {
    if (loc.kind == Location::kVertex && t[k] == loc.id) w[k] = 1.0;
    if (loc.kind == Location::kEdge && m.face_edges[f][k] == loc.id) {
      const bool forward = m.edges[loc.id].x == t[k];
      w[k] = forward ? 1.0 - loc.t : loc.t;
      w[(k + 1) % 3] = forward ? loc.t : 1.0 - loc.t;
    }
  }
  return w;
}

Location location_from_weights(const ExteriorMesh& m, std::uint32_t f, const glm::dvec3& w) {
  const auto& t = m.triangles[f];
  const int zeros = int(w.x == 0.0) + int(w.y == 0.0) + int(w.z == 0.0);
  if (zeros >= 2) return vertex_location(m, t[w.x != 0.0 ? 0 : (w.y != 0.0 ? 1 : 2)]);
  if (zeros == 1) {
    const int k = w[0] == 0.0 ? 1 : (w[1] == 0.0 ? 2 : 0);  // side k runs from corner k to k+1
    const std::uint32_t e = m.face_edges[f][k];
    const double wa = w[k], wb = w[(k + 1) % 3];
    return edge_location(m, e, m.edges[e].x == t[k] ? wb / (wa + wb) : wa / (wa + wb));
  }
  Location loc;
  loc.kind = Location::kFace;
  loc.id = f;
  loc.bary = w;
  loc.point = w.x * m.positions[t[0]] + w.y * m.positions[t[1]] + w.z * m.positions[t[2]];
  return loc;
}

std::uint32_t common_face(const ExteriorMesh& m, const Location& a, const Location& b) {
  for (std::uint32_t f : location_faces(m, a))
    if (location_in_face(m, b, f)) return f;
  return kNone;
}

std::uint32_t segment_face(const ExteriorMesh& m, const Location& a, const Location& b) {
  const std::uint32_t f = common_face(m, a, b);
  if (f == kNone || (location_sides(m, a, f) & location_sides(m, b, f)) != 0u) return kNone;
  return f;
}

bool segments_cross_in_face(const ExteriorMesh& m, std::uint32_t f, const Location& a, const Location& b,
                            const Location& c, const Location& d) {
  const glm::dvec2 pa = location_uv(m, a, f), pb = location_uv(m, b, f), pc = location_uv(m, c, f),
                   pd = location_uv(m, d, f);
  return orient2d(pa, pb, pc) * orient2d(pa, pb, pd) < 0 && orient2d(pc, pd, pa) * orient2d(pc, pd, pb) < 0;
}

Location location_between(const ExteriorMesh& m, const Location& a, const Location& b, double t) {
  const std::uint32_t f = common_face(m, a, b);
  glm::dvec3 w = (1.0 - t) * location_weights(m, a, f) + t * location_weights(m, b, f);
  w = glm::max(w, glm::dvec3(0.0));
  return location_from_weights(m, f, w / (w.x + w.y + w.z));
}

bool meets_exterior_off_rim(const ExteriorMesh& m, const std::array<glm::dvec3, 3>& corners,
                            const std::array<const Location*, 3>& rim, bool holders) {
  Aabb box;
  for (const glm::dvec3& p : corners) box.expand(p);
  // Called per face of S in the refiner's contact checks: one candidate buffer per thread.
  thread_local std::vector<std::uint32_t> near;
  near.clear();
  query_box(m.bvh, box, near);
  for (std::uint32_t t : near) {
    const auto& tri = m.triangles[t];
    const glm::dvec3 a = m.positions[tri[0]], b = m.positions[tri[1]], c = m.positions[tri[2]];
    bool holds = false;
    for (int k = 0; k < 3; ++k) holds = holds || (rim[std::size_t(k)] && location_in_face(m, *rim[std::size_t(k)], t));
    if (!holds) {
      if (triangles_intersect(corners, {a, b, c})) return true;
      continue;
    }
    for (int k = 0; k < 3 && holders; ++k)
      if (!rim[std::size_t(k)] && orient3d(a, b, c, corners[std::size_t(k)]) <= 0) return true;
  }
  return false;
}

std::string format_point(const glm::dvec3& p) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.9g, %.9g, %.9g)", p.x, p.y, p.z);
  return buffer;
}

}  // namespace fracref::rim
