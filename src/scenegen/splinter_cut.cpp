// The tree branch's splintered coarse crack. A flat cut across the branch would stay flat under
// the refiner: the branch's noise is stretched along the axis, so across a plane normal to the
// axis ψ hardly changes (∇ψ·n ≈ 0) and a flat disc is the least-energy sheet. Splinters, whose
// walls run along the fibres where the noise varies fastest, must come from the coarse cut.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <map>

#include "scenegen/scenegen_internal.hpp"
#include "util/error.hpp"

namespace fracref::scenegen_detail {
namespace {

// Two columns sharing a side, and the unit normal of that side (in x, y) from a towards b.
struct Wall {
  int a = 0, b = 0;
  glm::dvec2 normal{0.0};
};

// The columns around a disc vertex, in turning order; open: the vertex is on the rim (the fan
// does not close).
struct Fan {
  std::vector<int> columns;
  bool open = false;
};

struct Columns {
  std::uint32_t disc_vertices = 0;
  std::vector<glm::dvec2> centre;
  std::vector<double> lowest;  // per column, the least y of its corners
  std::vector<Wall> walls;
  std::vector<std::vector<int>> walls_of;             // per column, its walls
  std::vector<std::array<std::uint32_t, 3>> corners;  // per column, its disc vertices
  std::vector<Fan> fans;                              // per disc vertex
};

// Per disc vertex, its columns in turning order, starting inwards for a rim vertex (the disc is
// centred on the axis) so that its open fan is not split.
std::vector<Fan> find_fans(const TetSet& set, const Columns& c) {
  std::vector<Fan> fans(c.disc_vertices);
  for (std::size_t i = 0; i < c.corners.size(); ++i)
    for (const std::uint32_t v : c.corners[i]) fans[v].columns.push_back(int(i));
  for (std::uint32_t v = 0; v < c.disc_vertices; ++v) {
    Fan& fan = fans[v];
    const glm::dvec2 p(set.positions[v]);
    const glm::dvec2 in = glm::length(p) > 0.0 ? -glm::normalize(p) : glm::dvec2(1.0, 0.0);
    const auto angle = [&](int i) {
      const glm::dvec2 d = c.centre[i] - p;
      return std::atan2(in.x * d.y - in.y * d.x, glm::dot(in, d));
    };
    std::sort(fan.columns.begin(), fan.columns.end(), [&](int a, int b) { return angle(a) < angle(b); });
    // A fan of k triangles closes when they share k edges at v (each wall is an edge at 2 corners).
    std::size_t walls_at_v = 0;
    for (const int i : fan.columns)
      for (const int w : c.walls_of[i]) {
        const auto& o = c.corners[c.walls[w].a == i ? c.walls[w].b : c.walls[w].a];
        walls_at_v += std::find(o.begin(), o.end(), v) != o.end();
      }
    fan.open = walls_at_v / 2 < fan.columns.size();
  }
  return fans;
}

// The columns are the disc triangles: cylinder_tets writes prism i of layer l as tets
// 3 (l T + i) .. +2, and its vertices as layer l n + disc index.
Columns find_columns(const TetSet& set, int layers) {
  Columns c;
  const std::size_t count = set.tets.size() / (3 * std::size_t(layers));
  if (layers < 2 || layers % 2 || count * 3 * layers != set.tets.size() || set.positions.size() % (layers + 1))
    throw RunError("scenegen: splinter_cut needs a cylinder of an even number of layers");
  c.disc_vertices = std::uint32_t(set.positions.size() / (layers + 1));
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> first_at_edge;
  for (std::size_t i = 0; i < count; ++i) {
    std::array<std::uint32_t, 12> ids{};
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 4; ++j) ids[4 * k + j] = set.tets[3 * i + k][j] % c.disc_vertices;
    std::sort(ids.begin(), ids.end());
    const auto end = std::unique(ids.begin(), ids.end());
    if (end - ids.begin() != 3) throw RunError("scenegen: splinter_cut: a prism is not over one disc triangle");
    glm::dvec2 centre(0.0);
    for (int k = 0; k < 3; ++k) centre += glm::dvec2(set.positions[ids[k]]) / 3.0;
    c.centre.push_back(centre);
    c.corners.push_back({ids[0], ids[1], ids[2]});
    c.lowest.push_back(std::min({set.positions[ids[0]].y, set.positions[ids[1]].y, set.positions[ids[2]].y}));
    for (const auto& [p, q] : {std::pair{ids[0], ids[1]}, std::pair{ids[1], ids[2]}, std::pair{ids[0], ids[2]}}) {
      const auto [it, fresh] = first_at_edge.emplace(std::pair{p, q}, int(i));
      if (fresh) continue;
      const glm::dvec2 d = glm::dvec2(set.positions[q]) - glm::dvec2(set.positions[p]);
      glm::dvec2 n = glm::normalize(glm::dvec2(-d.y, d.x));
      if (glm::dot(n, centre - c.centre[it->second]) < 0.0) n = -n;
      c.walls.push_back({it->second, int(i), n});
    }
  }
  c.walls_of.resize(c.centre.size());
  for (std::size_t w = 0; w < c.walls.size(); ++w)
    for (const int i : {c.walls[w].a, c.walls[w].b}) c.walls_of[i].push_back(int(w));
  c.fans = find_fans(set, c);
  return c;
}

// Per column, how far from the middle (in layers, signed) its fibres pull out: the reach times
// the tension (0 where the column reaches down to the hinge, 1 at the far side) times the
// strength ζ at the middle, since strong fibres are the ones that pull out of the weaker wood
// around them rather than snap where they are bent most. The tension is taken at the column's
// lowest corner: near the hinge the halves hardly open, and a step there would let the refined
// pieces overlap. Splinters on the side of x > 0 (x < 0 when `flip`) stay with the lower half,
// those on the other side with the upper one.
std::vector<int> wanted_heights(const Columns& c, const Strength& strength, const SplinterOptions& o, double z) {
  std::vector<int> wanted(c.centre.size(), 0);
  for (std::size_t i = 0; i < c.centre.size(); ++i) {
    const double tension = std::max(0.0, (c.lowest[i] - o.front) / (o.radius - o.front));
    const double zeta = strength(glm::dvec3(c.centre[i], z));
    const int sign = (c.centre[i].x > 0.0) != o.flip ? 1 : -1;
    wanted[i] = sign * int(std::lround(o.reach * tension * zeta));
  }
  return wanted;
}

// Whether the columns of `fan` that break beyond layer k from the middle (on the side of k:
// above it for k >= 0, at or below it for k < 0) are one run, touching an end of an open fan;
// else the tets about that vertical edge at that layer would pinch a piece. When not, every
// other run is brought back to layer k.
bool unpinch_layer(const Fan& fan, int k, std::vector<int>& height) {
  const std::size_t n = fan.columns.size();
  const auto out = [&](std::size_t j) {
    const int h = height[fan.columns[j % n]];
    return k >= 0 ? h > k : h <= k;
  };
  std::vector<std::pair<std::size_t, std::size_t>> runs;  // (first, length), first < n
  std::size_t start = 0;  // a closed fan's runs are counted from a column that is not out
  while (!fan.open && start < n && out(start)) ++start;
  if (start == n) return false;
  for (std::size_t j = start; j < start + n; ++j)
    if (out(j) && (j == start || !out(j - 1) || (fan.open && j % n == 0)))
      runs.push_back({j % n, 1});
    else if (out(j))
      ++runs.back().second;
  const auto keeps = [&](const std::pair<std::size_t, std::size_t>& r) {
    return !fan.open || r.first == 0 || r.first + r.second == n;
  };
  if (runs.size() <= 1 && (runs.empty() || keeps(runs.front()))) return false;
  std::size_t best = runs.size();
  for (std::size_t r = 0; r < runs.size(); ++r)
    if (keeps(runs[r]) && (best == runs.size() || runs[r].second > runs[best].second)) best = r;
  for (std::size_t r = 0; r < runs.size(); ++r)
    for (std::size_t j = 0; r != best && j < runs[r].second; ++j)
      height[fan.columns[(runs[r].first + j) % n]] = k >= 0 ? k : k + 1;
  return true;
}

// unpinch_layer on every fan and layer; whether anything changed.
bool unpinch(const Columns& c, std::vector<int>& height) {
  bool changed = false;
  for (const Fan& fan : c.fans) {
    int lo = 0, hi = 0;
    for (const int i : fan.columns) lo = std::min(lo, height[i]), hi = std::max(hi, height[i]);
    for (int k = lo; k < hi; ++k) changed |= unpinch_layer(fan, k, height);
  }
  return changed;
}

// Brings back every column that breaks a wall rule of splinter_cut beside a neighbour (the
// lesser of two on opposite sides of the middle to it; the farther of two whose wall would
// close to the nearer's layer); whether anything changed.
bool settle_walls(const Columns& c, double min_slope, std::vector<int>& height) {
  bool changed = false;
  for (const Wall& w : c.walls) {
    int &a = height[w.a], &b = height[w.b];
    if (a * b < 0) {
      (std::abs(a) <= std::abs(b) ? a : b) = 0;
      changed = true;
    } else if (std::abs(a) != std::abs(b)) {
      const bool b_farther = std::abs(b) > std::abs(a);
      if ((b_farther ? w.normal.y : -w.normal.y) >= min_slope) continue;
      (b_farther ? b : a) = b_farther ? a : b;
      changed = true;
    }
  }
  return changed;
}

// Whether column i may break at h beside its neighbours' present heights: never above the
// middle beside one below it, and across each step wall the taller side (farther from the
// middle) lies away from the hinge.
bool opens(const Columns& c, const std::vector<int>& height, int i, int h, double min_slope) {
  for (const int wi : c.walls_of[i]) {
    const Wall& w = c.walls[wi];
    const int n = w.a == i ? w.b : w.a, hn = height[n];
    const double towards_n = w.a == i ? w.normal.y : -w.normal.y;
    if (h * hn < 0) return false;
    if (std::abs(h) > std::abs(hn) && -towards_n < min_slope) return false;
    if (std::abs(h) < std::abs(hn) && towards_n < min_slope) return false;
  }
  return true;
}

// From a flat cut, columns farthest from the hinge first, each column moves its break as far
// towards its wanted height as it may beside its neighbours (opens), until none can. Breaks only
// move away from the middle, so this ends; and every state opens.
std::vector<int> grow_splinters(const Columns& c, const std::vector<int>& wanted, double min_slope) {
  std::vector<int> order(c.centre.size()), height(c.centre.size(), 0);
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = int(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return c.centre[a].y > c.centre[b].y; });
  for (bool changed = true; changed;) {
    changed = false;
    for (const int i : order) {
      const int step = wanted[i] > 0 ? 1 : -1;
      for (int h = wanted[i]; h != height[i]; h -= step)
        if (opens(c, height, i, h, min_slope)) {
          height[i] = h, changed = true;
          break;
        }
    }
  }
  return height;
}

}  // namespace

SplinterCut splinter_cut(const TetSet& set, int layers, const Strength& strength, const SplinterOptions& options) {
  const Columns columns = find_columns(set, layers);
  SplinterCut cut;
  const double middle = 0.5 * (set.positions.front().z + set.positions.back().z);
  std::vector<int> wanted = wanted_heights(columns, strength, options, middle);
  for (int& h : wanted) h = std::clamp(h, 1 - layers / 2, layers / 2 - 1);
  cut.height = grow_splinters(columns, wanted, options.min_wall_slope);
  // Bringing a column back for one rule can break the other; every round only brings columns
  // back, so this ends (at worst at the flat cut, which keeps both).
  for (bool changed = true; changed;)
    changed = unpinch(columns, cut.height) | settle_walls(columns, options.min_wall_slope, cut.height);
  const std::size_t count = columns.centre.size();
  cut.side.resize(set.tets.size());
  for (std::size_t t = 0; t < set.tets.size(); ++t) {
    const int layer = int(t / (3 * count)), column = int(t / 3 % count);
    cut.side[t] = layer >= layers / 2 + cut.height[column] ? 1 : 0;
  }
  const TetFaces faces = tet_faces(set);
  std::vector<std::uint8_t> between(set.positions.size(), 0), joined(set.positions.size(), 0);
  for (std::size_t f = 0; f < faces.interior.size(); ++f) {
    const glm::uvec2 tets = faces.interior_tets[f];
    if (cut.side[tets.x] == cut.side[tets.y]) continue;
    const glm::uvec3 face = faces.interior[f];
    const bool cracked =
        (set.positions[face.x].y + set.positions[face.y].y + set.positions[face.z].y) / 3.0 > options.front;
    if (cracked) cut.faces.push_back(face);
    for (int i = 0; i < 3; ++i) between[face[i]] = 1, joined[face[i]] |= !cracked;
  }
  cut.opens.resize(set.positions.size());
  for (std::size_t v = 0; v < between.size(); ++v) cut.opens[v] = between[v] && !joined[v];
  return cut;
}

}  // namespace fracref::scenegen_detail
