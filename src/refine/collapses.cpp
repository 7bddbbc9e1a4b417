#include "refine/collapses.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geom/intersect.hpp"

namespace fracref {
namespace {

constexpr double kDegrees = 3.14159265358979323846 / 180.0;

glm::dvec3 at(const FractureSurface& s, std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); }
bool uses(const glm::uvec4& f, std::uint32_t v) { return f.x == v || f.y == v || f.z == v; }

void sort_unique(std::vector<std::uint32_t>& x) {
  std::sort(x.begin(), x.end());
  x.erase(std::unique(x.begin(), x.end()), x.end());
}

// One collapse: tip v into u, the faces on edge v–u removed, v's other faces moved to u.
struct Plan {
  std::uint32_t v = 0, u = 0;
  std::vector<std::uint32_t> removed, moved, star_vertices;
};

glm::uvec4 moved_face(glm::uvec4 f, std::uint32_t v, std::uint32_t u) {
  for (int c = 0; c < 3; ++c)
    if (f[c] == v) f[c] = u;
  return f;
}

// v's other ends of its junction edges, ascending.
std::vector<std::uint32_t> junction_neighbours(const FractureSurface& s, std::uint32_t v) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t k = s.vf_offsets[v]; k < s.vf_offsets[v + 1]; ++k) {
    const std::uint32_t f = s.vf_faces[k];
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t e = s.face_edges[3 * f + c];
      if (s.edge_special[e] != kEdgeNonManifold) continue;
      const glm::uvec2 ab = s.edges[e];
      if (ab.x == v || ab.y == v) out.push_back(ab.x == v ? ab.y : ab.x);
    }
  }
  sort_unique(out);
  return out;
}

// The ends of the two junction edges at v that are closest in angle, the nearer first, when
// closer than the hairpin's limit; none when v is not a hairpin's tip.
std::vector<std::uint32_t> hairpin_targets(const FractureSurface& s, std::uint32_t v, double cos_max) {
  if ((s.vertex_flags[v] & kVertexBoundary) || !(s.vertex_flags[v] & kVertexNonManifold)) return {};
  const std::vector<std::uint32_t> n = junction_neighbours(s, v);
  std::vector<glm::dvec3> dir;
  for (const std::uint32_t w : n) dir.push_back(at(s, w) - at(s, v));
  double best = cos_max;
  std::vector<std::uint32_t> pair;
  for (std::size_t i = 0; i < n.size(); ++i)
    for (std::size_t j = i + 1; j < n.size(); ++j) {
      const double li = glm::length(dir[i]), lj = glm::length(dir[j]);
      if (!(li > 0.0 && lj > 0.0)) continue;
      const double c = glm::dot(dir[i], dir[j]) / (li * lj);
      if (c > best) best = c, pair = lj < li ? std::vector<std::uint32_t>{n[j], n[i]} : std::vector<std::uint32_t>{n[i], n[j]};
    }
  return pair;
}

Plan make_plan(const FractureSurface& s, std::uint32_t v, std::uint32_t u) {
  Plan p{v, u, {}, {}, {}};
  for (const std::uint32_t w : {v, u})
    for (std::uint32_t k = s.vf_offsets[w]; k < s.vf_offsets[w + 1]; ++k) {
      const std::uint32_t f = s.vf_faces[k];
      const glm::uvec4 g = s.faces[f];
      if (uses(g, v) && uses(g, u)) p.removed.push_back(f);
      else if (w == v) p.moved.push_back(f);
      p.star_vertices.insert(p.star_vertices.end(), {g.x, g.y, g.z});
    }
  sort_unique(p.removed);
  sort_unique(p.star_vertices);
  return p;
}

// The vertices of the faces around w other than w, ascending; and the pieces on those faces.
void around(const FractureSurface& s, std::uint32_t w, std::vector<std::uint32_t>& vertices, std::vector<int>& pieces) {
  for (std::uint32_t k = s.vf_offsets[w]; k < s.vf_offsets[w + 1]; ++k) {
    const std::uint32_t f = s.vf_faces[k];
    for (int c = 0; c < 3; ++c)
      if (s.faces[f][c] != w) vertices.push_back(s.faces[f][c]);
    pieces.push_back(s.face_pieces[f].x), pieces.push_back(s.face_pieces[f].y);
  }
  sort_unique(vertices);
  std::sort(pieces.begin(), pieces.end());
  pieces.erase(std::unique(pieces.begin(), pieces.end()), pieces.end());
}

// The link condition: a vertex next to both v and u lies opposite edge v–u in a face, and a piece
// with faces at both v and u has one on the edge (else the collapse would pinch it at u).
bool link_condition(const FractureSurface& s, const Plan& p) {
  std::vector<std::uint32_t> nv, nu, opposite;
  std::vector<int> pv, pu, pe;
  around(s, p.v, nv, pv);
  around(s, p.u, nu, pu);
  for (const std::uint32_t f : p.removed) {
    const glm::uvec4 g = s.faces[f];
    opposite.push_back(g.x + g.y + g.z - p.v - p.u);
    pe.push_back(s.face_pieces[f].x), pe.push_back(s.face_pieces[f].y);
  }
  sort_unique(opposite);
  for (const std::uint32_t w : nv)
    if (w != p.u && std::binary_search(nu.begin(), nu.end(), w) && !std::binary_search(opposite.begin(), opposite.end(), w))
      return false;
  for (const int piece : pv)
    if (std::binary_search(pu.begin(), pu.end(), piece) && std::find(pe.begin(), pe.end(), piece) == pe.end())
      return false;
  return !p.removed.empty();
}

// No moved face turns by more than the limit or becomes degenerate, and the caller takes each.
bool moves_well(const FractureSurface& s, const Plan& p, const CollapseOptions& o) {
  const double cos_turn = std::cos(o.max_turn_degrees * kDegrees);
  for (const std::uint32_t f : p.moved) {
    const glm::uvec4 g = s.faces[f], h = moved_face(g, p.v, p.u);
    const glm::dvec3 n0 = glm::cross(at(s, g.y) - at(s, g.x), at(s, g.z) - at(s, g.x));
    const glm::dvec3 n1 = glm::cross(at(s, h.y) - at(s, h.x), at(s, h.z) - at(s, h.x));
    const double l0 = glm::length(n0), l1 = glm::length(n1);
    if (!(l1 > 0.0) || glm::dot(n0, n1) < cos_turn * l0 * l1) return false;
    if (o.reject_face && o.reject_face(h)) return false;
  }
  return true;
}

// The faces around the star's vertices, as a surface of their own (local vertex ids), with the
// collapse made when `collapsed`. Every edge with an end among the star's vertices has all its
// faces there: those are the edges the collapse changes.
FractureSurface patch(const FractureSurface& s, const Plan& p, bool collapsed, std::vector<std::uint32_t>& ids) {
  std::vector<std::uint32_t> faces;
  for (const std::uint32_t w : p.star_vertices)
    faces.insert(faces.end(), s.vf_faces.begin() + s.vf_offsets[w], s.vf_faces.begin() + s.vf_offsets[w + 1]);
  sort_unique(faces);
  ids.clear();
  for (const std::uint32_t f : faces) ids.insert(ids.end(), {s.faces[f].x, s.faces[f].y, s.faces[f].z});
  sort_unique(ids);
  const auto local = [&](std::uint32_t w) { return std::uint32_t(std::lower_bound(ids.begin(), ids.end(), w) - ids.begin()); };
  FractureSurface out;
  out.piece_count = s.piece_count;
  for (const std::uint32_t w : ids) out.positions.push_back(s.positions[w]);
  out.vertex_flags.assign(ids.size(), 0);
  for (const std::uint32_t f : faces) {
    glm::uvec4 g = s.faces[f];
    if (collapsed && uses(g, p.v) && uses(g, p.u)) continue;
    if (collapsed) g = moved_face(g, p.v, p.u);
    out.faces.push_back(glm::uvec4(local(g.x), local(g.y), local(g.z), 0u));
    out.face_pieces.push_back(s.face_pieces[f]);
  }
  rebuild_adjacency(out);
  return out;
}

// Per piece, V − E + F of its faces in `s`.
std::vector<long> euler_characteristics(const FractureSurface& s) {
  std::vector<long> chi(std::size_t(s.piece_count), 0);
  for (int piece = 0; piece < s.piece_count; ++piece)
    chi[std::size_t(piece)] = long(s.piece_vertex_counts[std::size_t(piece)]);
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    std::vector<int> pieces;
    for (std::uint32_t k = s.ef_offsets[e]; k < s.ef_offsets[e + 1]; ++k)
      pieces.insert(pieces.end(), {s.face_pieces[s.ef_faces[k]].x, s.face_pieces[s.ef_faces[k]].y});
    std::sort(pieces.begin(), pieces.end());
    pieces.erase(std::unique(pieces.begin(), pieces.end()), pieces.end());
    for (const int piece : pieces) --chi[std::size_t(piece)];
  }
  for (const glm::ivec2& fp : s.face_pieces) ++chi[std::size_t(fp.x)], ++chi[std::size_t(fp.y)];
  return chi;
}

// Collapsed, the patch is still a valid S at every edge the collapse changes, no two of its faces
// have one vertex set, and no piece changes its topology.
bool patch_stays_valid(const FractureSurface& s, const Plan& p) {
  std::vector<std::uint32_t> ids;
  const FractureSurface before = patch(s, p, false, ids);
  const FractureSurface after = patch(s, p, true, ids);
  std::vector<std::array<std::uint32_t, 3>> sets;
  for (const glm::uvec4& f : after.faces) {
    std::array<std::uint32_t, 3> t{f.x, f.y, f.z};
    std::sort(t.begin(), t.end());
    sets.push_back(t);
  }
  std::sort(sets.begin(), sets.end());
  if (std::adjacent_find(sets.begin(), sets.end()) != sets.end()) return false;
  std::vector<std::uint32_t> edges;
  for (std::uint32_t e = 0; e < after.edges.size(); ++e) {
    const glm::uvec2 ab = after.edges[e];
    if (std::binary_search(p.star_vertices.begin(), p.star_vertices.end(), ids[ab.x]) ||
        std::binary_search(p.star_vertices.begin(), p.star_vertices.end(), ids[ab.y]))
      edges.push_back(e);
  }
  return validate_edges(after, edges).empty() && euler_characteristics(after) == euler_characteristics(before);
}

// Drops the plans whose moved faces meet a face of S (or another plan's) other than where S
// connects them, until none does (a dropped plan's faces stay where they were, so the test runs
// again on the plans left).
void drop_crossing(const FractureSurface& s, std::vector<Plan>& plans) {
  const std::vector<glm::dvec3> x = double_positions(s);
  for (bool dropped = true; dropped && !plans.empty();) {
    std::vector<char> changed(s.faces.size(), 0);
    std::vector<TriangleIds> tris;
    std::vector<std::size_t> owner;
    for (std::size_t k = 0; k < plans.size(); ++k) {
      for (const std::uint32_t f : plans[k].removed) changed[f] = 1;
      for (const std::uint32_t f : plans[k].moved) {
        changed[f] = 1;
        const glm::uvec4 h = moved_face(s.faces[f], plans[k].v, plans[k].u);
        tris.push_back({h.x, h.y, h.z}), owner.push_back(k);
      }
    }
    // Only faces whose boxes meet a moved face's can meet it: the rest are left out of the search.
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    std::vector<std::pair<glm::dvec3, glm::dvec3>> boxes;
    for (const TriangleIds& h : tris) {
      boxes.emplace_back(glm::min(glm::min(x[h[0]], x[h[1]]), x[h[2]]), glm::max(glm::max(x[h[0]], x[h[1]]), x[h[2]]));
      lo = glm::min(lo, boxes.back().first), hi = glm::max(hi, boxes.back().second);
    }
    SelfIntersectionOptions o;
    o.query_faces = tris.size();
    for (std::uint32_t f = 0; f < s.faces.size(); ++f) {
      if (changed[f]) continue;
      const glm::uvec4 g = s.faces[f];
      const glm::dvec3 flo = glm::min(glm::min(x[g.x], x[g.y]), x[g.z]), fhi = glm::max(glm::max(x[g.x], x[g.y]), x[g.z]);
      if (glm::any(glm::lessThan(fhi, lo)) || glm::any(glm::greaterThan(flo, hi))) continue;
      if (std::any_of(boxes.begin(), boxes.end(), [&](const auto& b) {
            return !glm::any(glm::lessThan(fhi, b.first)) && !glm::any(glm::greaterThan(flo, b.second));
          }))
        tris.push_back({g.x, g.y, g.z});
    }
    std::vector<char> drop(plans.size(), 0);
    for (const auto& [i, j] : find_self_intersections(x, tris, o)) {
      drop[owner[i]] = 1;
      if (j < o.query_faces) drop[owner[j]] = 1;
    }
    dropped = std::find(drop.begin(), drop.end(), 1) != drop.end();
    std::size_t kept = 0;
    for (std::size_t k = 0; k < plans.size(); ++k)
      if (!drop[k]) {
        if (kept != k) plans[kept] = std::move(plans[k]);
        ++kept;
      }
    plans.resize(kept);
  }
}

void apply_plans(FractureSurface& s, const std::vector<Plan>& plans) {
  std::vector<std::uint8_t> change(s.faces.size(), 0);  // 1 removed, 2 moved
  std::vector<glm::uvec2> move_of(s.faces.size());
  for (const Plan& p : plans) {
    for (const std::uint32_t f : p.removed) change[f] = 1;
    for (const std::uint32_t f : p.moved) change[f] = 2, move_of[f] = {p.v, p.u};
  }
  std::size_t kept = 0;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    if (change[f] == 1) continue;
    s.faces[kept] = change[f] == 2 ? moved_face(s.faces[f], move_of[f].x, move_of[f].y) : s.faces[f];
    s.face_pieces[kept++] = s.face_pieces[f];
  }
  s.faces.resize(kept), s.face_pieces.resize(kept);
  rebuild_adjacency(s);
}

}  // namespace

std::vector<std::uint32_t> collapse_hairpin_tips(FractureSurface& s, const CollapseOptions& o) {
  if (!(o.max_hairpin_degrees > 0.0)) return {};
  const double cos_max = std::cos(o.max_hairpin_degrees * kDegrees);
  std::vector<char> touched(s.positions.size(), 0);
  std::vector<Plan> plans;
  for (std::uint32_t v = 0; v < s.positions.size(); ++v) {
    if (touched[v]) continue;
    for (const std::uint32_t u : hairpin_targets(s, v, cos_max)) {
      if (touched[u] || (s.vertex_flags[u] & kVertexBoundary)) continue;
      Plan p = make_plan(s, v, u);
      if (std::any_of(p.star_vertices.begin(), p.star_vertices.end(), [&](std::uint32_t w) { return touched[w] != 0; }))
        continue;
      if (!link_condition(s, p) || !moves_well(s, p, o) || !patch_stays_valid(s, p)) continue;
      for (const std::uint32_t w : p.star_vertices) touched[w] = 1;
      plans.push_back(std::move(p));
      break;
    }
  }
  drop_crossing(s, plans);
  if (plans.empty()) return {};
  apply_plans(s, plans);
  std::vector<std::uint32_t> tips;
  for (const Plan& p : plans) tips.push_back(p.v);
  return tips;
}

}  // namespace fracref
