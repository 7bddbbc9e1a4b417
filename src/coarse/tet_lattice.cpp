// A tet mesh whose hull lies on the exterior: lattice tets cut by the exterior (marching
// tetrahedra on the inside/outside sign), after warping lattice vertices that lie close to the
// exterior onto it, in the manner of isosurface stuffing (Labelle and Shewchuk 2007).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "geom/bvh.hpp"
#include "coarse/tet_lattice.hpp"
#include "coarse/tet_tables.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using Edge = std::pair<std::uint32_t, std::uint32_t>;

// Where the segment from `in` (inside) to `out` first leaves the exterior.
glm::dvec3 crossing(const Bvh& bvh, const glm::dvec3& in, const glm::dvec3& out) {
  Aabb box;
  box.expand(in);
  box.expand(out);
  std::vector<std::uint32_t> hits;
  query_box(bvh, box, hits);
  double best = std::numeric_limits<double>::infinity();
  const glm::dvec3 d = out - in;
  for (const std::uint32_t t : hits) {
    const glm::dvec3 a = bvh.positions[bvh.triangles[t][0]], b = bvh.positions[bvh.triangles[t][1]],
                     c = bvh.positions[bvh.triangles[t][2]];
    const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0) continue;
    const glm::dvec3 s = in - a;
    const double u = glm::dot(s, p) / det;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(d, q) / det, t_hit = glm::dot(e2, q) / det;
    if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t_hit >= 0.0 && t_hit <= 1.0) best = std::min(best, t_hit);
  }
  // A crossing missed by rounding (the exact inside test and this one disagree at a grazing
  // edge): the exterior point nearest the middle.
  if (best == std::numeric_limits<double>::infinity()) return closest_point(bvh, 0.5 * (in + out)).point;
  return in + best * d;
}

class Stuffer {
 public:
  Stuffer(const std::vector<glm::dvec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles,
          const LatticeSpec& spec, double warp)
      : lattice_(box_lattice(spec)), bvh_(build_bvh(positions, triangles)), warp_(warp) {}
  TetSet run();

 private:
  void classify();
  void warp();
  std::uint32_t cut(std::uint32_t a, std::uint32_t b) const;
  void stencil(const glm::uvec4& tet);
  void wedge(std::array<std::uint32_t, 6> v);
  void pyramid(const std::array<std::uint32_t, 4>& q, std::uint32_t apex);
  void emit(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) { out_.push_back({a, b, c, d}); }

  TetSet lattice_;
  Bvh bvh_;
  double warp_;
  std::vector<int> sign_;           // -1 inside, +1 outside, 0 on the exterior (warped)
  std::vector<Edge> edges_;         // lattice edges, sorted
  std::vector<glm::dvec3> cuts_;    // per edge, its crossing (edges with a sign change)
  std::vector<std::uint8_t> has_cut_;
  std::vector<std::uint32_t> cut_id_;
  std::vector<glm::uvec4> out_;
};

void Stuffer::classify() {
  sign_.resize(lattice_.positions.size());
  for (std::size_t v = 0; v < sign_.size(); ++v) sign_[v] = point_in_mesh(bvh_, lattice_.positions[v]) ? -1 : 1;
  for (const glm::uvec4& t : lattice_.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) edges_.push_back(Edge(std::min(t[i], t[j]), std::max(t[i], t[j])));
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
  cuts_.resize(edges_.size());
  has_cut_.assign(edges_.size(), 0);
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    const auto [a, b] = edges_[e];
    if (sign_[a] == sign_[b]) continue;
    const bool a_in = sign_[a] < 0;
    cuts_[e] = crossing(bvh_, lattice_.positions[a_in ? a : b], lattice_.positions[a_in ? b : a]);
    has_cut_[e] = 1;
  }
}

// A lattice vertex with a crossing closer than warp_ times the edge's length moves onto the
// nearest such crossing; the edges at it then have none (avoids slivers).
void Stuffer::warp() {
  std::vector<std::vector<std::uint32_t>> at(lattice_.positions.size());
  for (std::uint32_t e = 0; e < edges_.size(); ++e)
    if (has_cut_[e]) at[edges_[e].first].push_back(e), at[edges_[e].second].push_back(e);
  for (std::uint32_t v = 0; v < at.size(); ++v) {
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t best_edge = 0;
    for (const std::uint32_t e : at[v]) {
      if (!has_cut_[e]) continue;
      const glm::dvec3 p = lattice_.positions[edges_[e].first], q = lattice_.positions[edges_[e].second];
      const double d = glm::distance(cuts_[e], lattice_.positions[v]);
      if (d < warp_ * glm::distance(p, q) && d < best) best = d, best_edge = e;
    }
    if (best == std::numeric_limits<double>::infinity()) continue;
    lattice_.positions[v] = cuts_[best_edge];
    sign_[v] = 0;
    for (const std::uint32_t e : at[v]) has_cut_[e] = 0;
  }
  cut_id_.assign(edges_.size(), 0);
  std::uint32_t next = std::uint32_t(lattice_.positions.size());
  for (std::uint32_t e = 0; e < edges_.size(); ++e)
    if (has_cut_[e]) cut_id_[e] = next++;
}

std::uint32_t Stuffer::cut(std::uint32_t a, std::uint32_t b) const {
  const auto it = std::lower_bound(edges_.begin(), edges_.end(), Edge(std::min(a, b), std::max(a, b)));
  return cut_id_[std::size_t(it - edges_.begin())];
}

// Splits a wedge (bottom v0 v1 v2, top v3 v4 v5, vk over vk+3) into three tets, each side quad
// cut from its lowest id, so that neighbours agree (Dompierre et al. 1999).
void Stuffer::wedge(std::array<std::uint32_t, 6> v) {
  int m = int(std::min_element(v.begin(), v.end()) - v.begin());
  if (m >= 3) {
    std::rotate(v.begin(), v.begin() + 3, v.end());
    m -= 3;
  }
  const std::array<std::uint32_t, 6> w{v[m], v[(m + 1) % 3], v[(m + 2) % 3], v[m + 3], v[(m + 1) % 3 + 3], v[(m + 2) % 3 + 3]};
  if (std::min(w[1], w[5]) < std::min(w[2], w[4])) {
    emit(w[0], w[1], w[2], w[5]), emit(w[0], w[1], w[5], w[4]), emit(w[0], w[4], w[5], w[3]);
  } else {
    emit(w[0], w[1], w[2], w[4]), emit(w[0], w[4], w[2], w[5]), emit(w[0], w[4], w[5], w[3]);
  }
}

void Stuffer::pyramid(const std::array<std::uint32_t, 4>& q, std::uint32_t apex) {
  const int m = int(std::min_element(q.begin(), q.end()) - q.begin());
  if (m % 2 == 0) emit(q[0], q[1], q[2], apex), emit(q[0], q[2], q[3], apex);
  else emit(q[1], q[2], q[3], apex), emit(q[1], q[3], q[0], apex);
}

// The inside part of one lattice tet (marching tetrahedra with on-surface vertices).
void Stuffer::stencil(const glm::uvec4& tet) {
  std::vector<std::uint32_t> in, on, out;
  for (int i = 0; i < 4; ++i) (sign_[tet[i]] < 0 ? in : sign_[tet[i]] == 0 ? on : out).push_back(tet[i]);
  if (out.empty()) {
    if (!in.empty()) emit(tet.x, tet.y, tet.z, tet.w);
    return;
  }
  if (in.empty()) return;
  if (in.size() == 1 && on.empty()) emit(in[0], cut(in[0], out[0]), cut(in[0], out[1]), cut(in[0], out[2]));
  else if (in.size() == 1 && on.size() == 1) emit(in[0], on[0], cut(in[0], out[0]), cut(in[0], out[1]));
  else if (in.size() == 1) emit(in[0], on[0], on[1], cut(in[0], out[0]));
  else if (in.size() == 2 && on.empty())
    wedge({in[0], cut(in[0], out[0]), cut(in[0], out[1]), in[1], cut(in[1], out[0]), cut(in[1], out[1])});
  else if (in.size() == 2) pyramid({in[0], in[1], cut(in[1], out[0]), cut(in[0], out[0])}, on[0]);
  else wedge({in[0], in[1], in[2], cut(in[0], out[0]), cut(in[1], out[0]), cut(in[2], out[0])});
}

TetSet Stuffer::run() {
  classify();
  warp();
  for (const glm::uvec4& t : lattice_.tets) stencil(t);
  std::vector<glm::dvec3> positions = lattice_.positions;
  for (std::uint32_t e = 0; e < edges_.size(); ++e)
    if (has_cut_[e]) positions.push_back(cuts_[e]);
  // Compact: keep the vertices the tets use, in id order.
  std::vector<std::uint32_t> id(positions.size(), 0xffffffffu);
  for (const glm::uvec4& t : out_)
    for (int c = 0; c < 4; ++c) id[t[c]] = 0;
  TetSet set;
  for (std::uint32_t v = 0; v < positions.size(); ++v)
    if (id[v] == 0) id[v] = std::uint32_t(set.positions.size()), set.positions.push_back(positions[v]);
  for (const glm::uvec4& t : out_) {
    set.tets.push_back({id[t.x], id[t.y], id[t.z], id[t.w]});
    if (tet_volume(set, std::uint32_t(set.tets.size() - 1)) < 0.0) std::swap(set.tets.back().z, set.tets.back().w);
  }
  if (set.tets.empty()) throw RunError("stuffing: no lattice tet lies inside the exterior");
  keep_largest_part(set);
  return set;
}

}  // namespace

TetSet stuffed_tets(const std::vector<glm::dvec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                    const LatticeSpec& spec, double warp) {
  return Stuffer(positions, triangles, spec, warp).run();
}

TetSet box_lattice(const LatticeSpec& spec) {
  TetSet set;
  const glm::ivec3 n = spec.cells;
  const auto id = [&](int i, int j, int k) { return std::uint32_t(i + (n.x + 1) * (j + (n.y + 1) * k)); };
  for (int k = 0; k <= n.z; ++k)
    for (int j = 0; j <= n.y; ++j)
      for (int i = 0; i <= n.x; ++i) {
        const glm::ivec3 g(i, j, k);
        glm::dvec3 p;
        for (int a = 0; a < 3; ++a)
          p[a] = g[a] == n[a] ? spec.hi[a] : spec.lo[a] + (spec.hi[a] - spec.lo[a]) * double(g[a]) / double(n[a]);
        set.positions.push_back(p);
      }
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i)
        for (int p = 0; p < 6; ++p) {
          glm::ivec3 g(i, j, k);
          glm::uvec4 t;
          t[0] = id(g.x, g.y, g.z);
          for (int s = 0; s < 3; ++s) {
            g[kKuhn[p][s]] += 1;
            t[s + 1] = id(g.x, g.y, g.z);
          }
          if (p >= 3) std::swap(t[2], t[3]);
          set.tets.push_back(t);
        }
  return set;
}

double tet_volume(const TetSet& set, std::uint32_t t) {
  const glm::uvec4& k = set.tets[t];
  const glm::dvec3 a = set.positions[k.x];
  return glm::dot(set.positions[k.y] - a, glm::cross(set.positions[k.z] - a, set.positions[k.w] - a)) / 6.0;
}

InteriorFaces interior_faces(const TetSet& set) {
  struct Key {
    glm::uvec3 v;
    std::uint32_t tet;
  };
  std::vector<Key> keys;
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (const auto& f : kTetFaces) keys.push_back({sorted3({set.tets[t][f[0]], set.tets[t][f[1]], set.tets[t][f[2]]}), t});
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) { return less3(a.v, b.v) || (a.v == b.v && a.tet < b.tet); });
  InteriorFaces out;
  for (std::size_t i = 0; i + 1 < keys.size(); ++i)
    if (keys[i].v == keys[i + 1].v) out.faces.push_back(keys[i].v), out.tets.push_back({keys[i].tet, keys[i + 1].tet});
  return out;
}

void keep_largest_part(TetSet& set) {
  const InteriorFaces faces = interior_faces(set);
  std::vector<std::uint32_t> root(set.tets.size());
  std::iota(root.begin(), root.end(), 0u);
  const auto find = [&root](std::uint32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (const glm::uvec2& t : faces.tets) {
    const std::uint32_t a = find(t.x), b = find(t.y);
    root[std::max(a, b)] = std::min(a, b);
  }
  std::vector<std::size_t> size(set.tets.size(), 0);
  for (std::uint32_t t = 0; t < set.tets.size(); ++t) ++size[find(t)];
  const std::uint32_t best = std::uint32_t(std::max_element(size.begin(), size.end()) - size.begin());
  std::vector<std::uint32_t> id(set.positions.size(), 0xffffffffu);
  TetSet out;
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    if (find(t) == best)
      for (int c = 0; c < 4; ++c) id[set.tets[t][c]] = 0;
  for (std::uint32_t v = 0; v < set.positions.size(); ++v)
    if (id[v] == 0) id[v] = std::uint32_t(out.positions.size()), out.positions.push_back(set.positions[v]);
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    if (find(t) == best) out.tets.push_back({id[set.tets[t].x], id[set.tets[t].y], id[set.tets[t].z], id[set.tets[t].w]});
  set = std::move(out);
}

TetSet stuff_inside(const std::vector<glm::dvec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                    double cells_per_diagonal, double warp) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const glm::dvec3& p : positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double h = glm::length(hi - lo) / cells_per_diagonal;
  LatticeSpec spec;
  spec.lo = lo - 1.5 * h;
  for (int a = 0; a < 3; ++a) spec.cells[a] = int(std::ceil((hi[a] - lo[a]) / h)) + 3;
  spec.hi = spec.lo + h * glm::dvec3(spec.cells);
  return stuffed_tets(positions, triangles, spec, warp);
}

}  // namespace fracref
