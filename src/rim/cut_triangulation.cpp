// Constrained triangulation of one cut triangle (rim/cut_triangulation.hpp) in its barycentric
// plane (exact orient2d):
// boundary points split their side, interior points split the triangle holding them, each
// constraint is recovered by flipping the edges it crosses (Sloan 1993), and free edges are then
// flipped toward Delaunay, judged by the angles of the 3D triangles.
#include <cmath>
#include <deque>
#include <map>
#include <numbers>
#include <set>

#include "geom/angles.hpp"
#include "geom/predicates.hpp"
#include "rim/cut_triangulation.hpp"
#include "rim/exterior_mesh.hpp"
#include "util/error.hpp"

namespace fracref::rim {
namespace {

using Edge = std::pair<std::uint32_t, std::uint32_t>;
using Tri = std::array<std::uint32_t, 3>;

Edge undirected(std::uint32_t a, std::uint32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; }

class Triangulation {
 public:
  explicit Triangulation(const CutTriangle& in) : in_(in) {}

  std::vector<Tri> run() {
    add({0, 1, 2});
    for (int k = 0; k < 3; ++k) insert_side(k);
    for (std::uint32_t p : in_.interior) insert_interior(p);
    for (const auto& [a, b] : in_.constraints) insert_constraint(a, b);
    if (in_.delaunay) improve();
    for (int pass = 0; pass < 4 && flip_away(); ++pass) {
    }
    std::vector<Tri> out;
    for (std::size_t t = 0; t < tris_.size(); ++t)
      if (alive_[t]) out.push_back(tris_[t]);
    return out;
  }

 private:
  int orient(std::uint32_t a, std::uint32_t b, std::uint32_t c) const { return orient2d(in_.uv[a], in_.uv[b], in_.uv[c]); }

  void add(const Tri& t) {
    const std::uint32_t id = std::uint32_t(tris_.size());
    tris_.push_back(t);
    alive_.push_back(1);
    for (int k = 0; k < 3; ++k) edge_tri_[{t[k], t[(k + 1) % 3]}] = id;
  }
  void remove(std::uint32_t id) {
    alive_[id] = 0;
    const Tri& t = tris_[id];
    for (int k = 0; k < 3; ++k) edge_tri_.erase({t[k], t[(k + 1) % 3]});
  }
  // The triangle holding directed edge a->b and its third vertex, or kNone.
  std::uint32_t tri_of(std::uint32_t a, std::uint32_t b) const {
    auto it = edge_tri_.find({a, b});
    return it == edge_tri_.end() ? kNone : it->second;
  }
  std::uint32_t third(std::uint32_t t, std::uint32_t a, std::uint32_t b) const {
    for (std::uint32_t v : tris_[t])
      if (v != a && v != b) return v;
    return kNone;
  }

  // Points of side k, inserted in order from corner k, each splitting the boundary edge from
  // the previous one to corner k+1.
  void insert_side(int k) {
    std::uint32_t prev = std::uint32_t(k);
    const std::uint32_t end = std::uint32_t((k + 1) % 3);
    const glm::dvec2 dir = in_.uv[end] - in_.uv[std::uint32_t(k)];
    for (std::uint32_t p : in_.side_points[k]) {
      if (!(glm::dot(in_.uv[p] - in_.uv[prev], dir) > 0.0) || !(glm::dot(in_.uv[end] - in_.uv[p], dir) > 0.0))
        throw RunError("two points on side " + std::to_string(k) + " coincide or are out of order");
      const std::uint32_t t = tri_of(prev, end);
      const std::uint32_t z = third(t, prev, end);
      remove(t);
      add({prev, p, z});
      add({p, end, z});
      prev = p;
    }
  }

  void insert_interior(std::uint32_t p) {
    for (std::uint32_t t = 0; t < tris_.size(); ++t) {
      if (!alive_[t]) continue;
      const Tri tri = tris_[t];
      int o[3], zeros = 0;
      bool outside = false;
      for (int k = 0; k < 3; ++k) {
        o[k] = orient(tri[k], tri[(k + 1) % 3], p);
        outside |= o[k] < 0;
        zeros += o[k] == 0;
      }
      if (outside) continue;
      if (zeros >= 2) throw RunError("two points coincide");
      remove(t);
      if (zeros == 0) {
        for (int k = 0; k < 3; ++k) add({tri[k], tri[(k + 1) % 3], p});
        return;
      }
      const int k = o[0] == 0 ? 0 : (o[1] == 0 ? 1 : 2);
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
      const std::uint32_t n = tri_of(b, a);
      if (n == kNone) throw RunError("an interior point lies on the triangle's side");
      const std::uint32_t d = third(n, a, b);
      remove(n);
      add({a, p, c});
      add({p, b, c});
      add({b, p, d});
      add({p, a, d});
      return;
    }
    throw RunError("an interior point lies outside the triangle");
  }

  bool crosses(std::uint32_t a, std::uint32_t b, std::uint32_t u, std::uint32_t v) const {
    if (u == a || u == b || v == a || v == b) return false;
    return orient(a, b, u) * orient(a, b, v) < 0 && orient(u, v, a) * orient(u, v, b) < 0;
  }

  std::vector<Edge> crossing_edges(std::uint32_t a, std::uint32_t b) const {
    std::vector<Edge> out;
    for (const auto& [e, t] : edge_tri_) {
      if (e.first > e.second || !crosses(a, b, e.first, e.second)) continue;
      if (constrained_.count(e)) throw RunError("two traced paths cross");
      out.push_back(e);
    }
    return out;
  }

  void insert_constraint(std::uint32_t a, std::uint32_t b) {
    if (a == b) throw RunError("a traced segment has no length");
    for (std::uint32_t w = 0; w < in_.uv.size(); ++w) {
      if (w == a || w == b || orient(a, b, w) != 0) continue;
      const glm::dvec2 d = in_.uv[b] - in_.uv[a];
      if (glm::dot(in_.uv[w] - in_.uv[a], d) > 0.0 && glm::dot(in_.uv[b] - in_.uv[w], d) > 0.0)
        throw RunError("a traced segment passes through another traced point");
    }
    std::deque<Edge> queue;
    for (const Edge& e : crossing_edges(a, b)) queue.push_back(e);
    std::size_t guard = 0;
    const std::size_t limit = 64 + 16 * tris_.size() * tris_.size();
    while (!queue.empty()) {
      if (++guard > limit) throw RunError("a traced segment could not be recovered");
      const auto [u, v] = queue.front();
      queue.pop_front();
      const std::uint32_t t1 = tri_of(u, v), t2 = tri_of(v, u);
      const std::uint32_t x = third(t1, u, v), y = third(t2, u, v);
      if (orient(u, y, x) <= 0 || orient(y, v, x) <= 0) {
        queue.push_back({u, v});
        continue;
      }
      flip(t1, t2, u, v, x, y);
      if (crosses(a, b, x, y)) queue.push_back({x, y});
    }
    if (tri_of(a, b) == kNone && tri_of(b, a) == kNone) throw RunError("a traced segment could not be recovered");
    constrained_.insert(undirected(a, b));
  }

  // t1 = (u, v, x) and t2 = (v, u, y) become (u, y, x) and (y, v, x).
  void flip(std::uint32_t t1, std::uint32_t t2, std::uint32_t u, std::uint32_t v, std::uint32_t x, std::uint32_t y) {
    remove(t1);
    remove(t2);
    add({u, y, x});
    add({y, v, x});
  }

  // Lawson flips of free interior edges whose opposite angles sum to more than pi (the Delaunay
  // criterion, on the 3D shapes); a flip needs a strictly convex quad. Capped, so it ends.
  void improve() {
    const std::size_t cap = 16 * tris_.size() + 64;
    std::size_t flips = 0;
    for (bool changed = true; changed && flips < cap;) {
      changed = false;
      std::vector<Edge> edges;
      for (const auto& [e, t] : edge_tri_)
        if (e.first < e.second && edge_tri_.count({e.second, e.first}) && !constrained_.count(e)) edges.push_back(e);
      for (const auto& [u, v] : edges) {
        const std::uint32_t t1 = tri_of(u, v), t2 = tri_of(v, u);
        if (t1 == kNone || t2 == kNone) continue;
        const std::uint32_t x = third(t1, u, v), y = third(t2, u, v);
        const double sum = corner_angle(in_.xyz[x], in_.xyz[u], in_.xyz[v]) + corner_angle(in_.xyz[y], in_.xyz[u], in_.xyz[v]);
        if (sum <= std::numbers::pi + 1e-12 || orient(u, y, x) <= 0 || orient(y, v, x) <= 0) continue;
        flip(t1, t2, u, v, x, y);
        changed = true;
        if (++flips >= cap) break;
      }
    }
  }

  // Flips each free interior edge of in_.avoid whose quad is strictly convex; true if any was.
  bool flip_away() {
    bool any = false;
    for (const auto& [a, b] : in_.avoid) {
      const std::uint32_t t1 = tri_of(a, b), t2 = tri_of(b, a);
      if (t1 == kNone || t2 == kNone || constrained_.count(undirected(a, b))) continue;
      const std::uint32_t x = third(t1, a, b), y = third(t2, a, b);
      if (orient(a, y, x) <= 0 || orient(y, b, x) <= 0) continue;
      flip(t1, t2, a, b, x, y);
      any = true;
    }
    return any;
  }

  const CutTriangle& in_;
  std::vector<Tri> tris_;
  std::vector<char> alive_;
  std::map<Edge, std::uint32_t> edge_tri_;  // directed edge -> triangle
  std::set<Edge> constrained_;              // undirected
};

}  // namespace

std::vector<std::array<std::uint32_t, 3>> triangulate_cut_triangle(const CutTriangle& input) {
  return Triangulation(input).run();
}

}  // namespace fracref::rim
