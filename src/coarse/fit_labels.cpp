#include "coarse/fit_labels.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <utility>

#include "coarse/coarse_internal.hpp"
#include "coarse/tet_tables.hpp"

namespace fracref::coarse_detail {
namespace {

using EdgeKey = std::uint64_t;

EdgeKey edge_key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b); }

// (edge, tet) for every edge of every tet, sorted.
std::vector<std::pair<EdgeKey, std::uint32_t>> edge_tets(const TetSet& set) {
  std::vector<std::pair<EdgeKey, std::uint32_t>> out;
  out.reserve(6 * set.tets.size());
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) out.emplace_back(edge_key(set.tets[t][a], set.tets[t][b]), t);
  std::sort(out.begin(), out.end());
  return out;
}

// The two corners of tet t other than the edge's.
std::array<std::uint32_t, 2> link(const glm::uvec4& t, EdgeKey e) {
  std::array<std::uint32_t, 2> out{};
  int n = 0;
  for (int k = 0; k < 4; ++k)
    if (t[k] != std::uint32_t(e >> 32) && t[k] != std::uint32_t(e)) out[n++ & 1] = t[k];
  return out;
}

// The tets of one edge in order around it (consecutive tets share a face), starting at an end
// of the fan when the edge is on the hull (open = true).
std::vector<std::uint32_t> fan_order(const TetSet& set, EdgeKey e, const std::uint32_t* tets, std::size_t n, bool& open) {
  std::map<std::uint32_t, std::vector<std::uint32_t>> at;  // link vertex -> tets
  for (std::size_t k = 0; k < n; ++k)
    for (std::uint32_t v : link(set.tets[tets[k]], e)) at[v].push_back(tets[k]);
  std::uint32_t start = tets[0], from = UINT32_MAX;
  open = false;
  for (const auto& [v, ts] : at)
    if (ts.size() == 1 && !open) open = true, start = ts[0], from = v;
  std::vector<std::uint32_t> order{start};
  for (std::size_t k = 1; k < n; ++k) {
    const auto l = link(set.tets[order.back()], e);
    const std::uint32_t v = l[0] == from ? l[1] : l[0];
    const auto& next = at[v];
    const auto it = std::find_if(next.begin(), next.end(), [&](std::uint32_t t) { return t != order.back(); });
    if (it == next.end() || std::find(order.begin(), order.end(), *it) != order.end()) break;
    order.push_back(*it), from = v;
  }
  return order;
}

// Runs of equal labels along the fan: (first position, length); a closed fan's last run joins its first.
std::vector<std::pair<std::size_t, std::size_t>> runs(const std::vector<int>& seq, bool open) {
  std::vector<std::pair<std::size_t, std::size_t>> r;
  for (std::size_t k = 0; k < seq.size(); ++k) {
    if (k == 0 || seq[k] != seq[k - 1]) r.emplace_back(k, 0);
    ++r.back().second;
  }
  if (!open && r.size() > 1 && seq.front() == seq.back()) {
    r.front().first = r.back().first, r.front().second += r.back().second;
    r.pop_back();
  }
  return r;
}

// Relabels the tets of one edge (in fan order) when a label holds two runs around it (its piece
// would touch itself along the edge), or three labels meet at a hull edge: of the moves that
// give a bad run its neighbour's higher label or a neighbour run the bad run's higher label (so
// that labels only grow and the repair ends), the one moving fewest tets, none locked. Returns
// the tets moved.
std::size_t untangle_fan(const std::vector<std::uint32_t>& fan, bool open, std::vector<int>& label,
                         const std::vector<bool>& locked) {
  std::vector<int> seq;
  for (std::uint32_t t : fan) seq.push_back(label[t]);
  const auto r = runs(seq, open);
  const std::size_t m = r.size();
  std::map<int, int> count;
  for (const auto& [first, length] : r) ++count[seq[first]];
  const bool three = open && count.size() >= 3;
  std::size_t best_run = m, best_size = SIZE_MAX;
  int best_label = 0;
  auto consider = [&](std::size_t k, int to) {
    if (to <= seq[r[k].first] || r[k].second >= best_size) return;
    for (std::size_t i = 0; i < r[k].second; ++i)
      if (locked[fan[(r[k].first + i) % fan.size()]]) return;
    best_run = k, best_size = r[k].second, best_label = to;
  };
  for (std::size_t k = 0; k < m; ++k) {
    const bool bad = three ? (k > 0 && k + 1 < m) : count[seq[r[k].first]] > 1;
    if (!bad) continue;
    for (const std::size_t n : {(k + m - 1) % m, (k + 1) % m}) {
      if (open && ((k == 0 && n == m - 1) || (k == m - 1 && n == 0))) continue;
      consider(k, seq[r[n].first]);
      consider(n, seq[r[k].first]);
    }
  }
  if (best_run == m) return 0;
  for (std::size_t i = 0; i < best_size; ++i) label[fan[(r[best_run].first + i) % fan.size()]] = best_label;
  return best_size;
}

}  // namespace

std::vector<bool> touches_hull(const TetSet& set) {
  std::vector<std::pair<glm::uvec3, std::uint32_t>> faces;
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (const auto& f : kTetFaces) faces.emplace_back(sorted_key(glm::uvec3(set.tets[t][f[0]], set.tets[t][f[1]], set.tets[t][f[2]])), t);
  std::sort(faces.begin(), faces.end(), [](const auto& x, const auto& y) { return key_less(x.first, y.first) || (x.first == y.first && x.second < y.second); });
  std::vector<bool> on_hull(set.positions.size(), false), out(set.tets.size(), false);
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].first == faces[i].first) ++j;
    if (j - i == 1)
      for (int k = 0; k < 3; ++k) on_hull[faces[i].first[k]] = true;
    i = j;
  }
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) out[t] = out[t] || on_hull[set.tets[t][k]];
  return out;
}

std::size_t merge_islands(std::size_t tets, const InteriorFaces& faces, std::vector<int>& label, double fraction) {
  std::size_t moved = 0;
  for (int round = 0; round < 8; ++round) {
    MinUnion parts(tets);
    for (const glm::uvec2& f : faces.tets)
      if (label[f.x] == label[f.y]) parts.unite(f.x, f.y);
    std::vector<std::uint32_t> size(tets, 0), root(tets);
    std::map<int, std::uint32_t> largest;  // per label, its largest part's size
    for (std::uint32_t t = 0; t < tets; ++t) ++size[root[t] = parts.find(t)];
    for (std::uint32_t t = 0; t < tets; ++t) largest[label[t]] = std::max(largest[label[t]], size[root[t]]);
    std::map<std::uint32_t, std::map<int, std::uint32_t>> touching;  // stray part -> label -> faces
    for (const glm::uvec2& f : faces.tets)
      for (int s = 0; s < 2; ++s) {
        const std::uint32_t a = s ? f.y : f.x, b = s ? f.x : f.y, r = root[a];
        if (label[a] != label[b] && size[r] < largest[label[a]] && size[r] <= fraction * largest[label[a]])
          ++touching[r][label[b]];
      }
    if (touching.empty()) break;
    for (std::uint32_t t = 0; t < tets; ++t) {
      auto it = touching.find(root[t]);
      if (it == touching.end()) continue;
      const auto best = std::max_element(it->second.begin(), it->second.end(),
                                         [](const auto& x, const auto& y) { return x.second < y.second; });
      label[t] = best->first, ++moved;
    }
  }
  return moved;
}

std::size_t untangle_edges(const TetSet& set, std::vector<int>& label, const std::vector<bool>& locked) {
  const auto pairs = edge_tets(set);
  std::vector<std::uint32_t> tets;
  std::size_t moved = 0;
  for (int round = 0; round < 64; ++round) {
    std::size_t now = 0;
    for (std::size_t i = 0; i < pairs.size();) {
      std::size_t j = i + 1;
      while (j < pairs.size() && pairs[j].first == pairs[i].first) ++j;
      tets.clear();
      bool mixed = false;
      for (std::size_t k = i; k < j; ++k) tets.push_back(pairs[k].second), mixed = mixed || label[pairs[k].second] != label[pairs[i].second];
      if (mixed && j - i >= 2) {
        bool open = false;
        const std::vector<std::uint32_t> fan = fan_order(set, pairs[i].first, tets.data(), tets.size(), open);
        now += untangle_fan(fan, open, label, locked);
      }
      i = j;
    }
    moved += now;
    if (now == 0) break;
  }
  return moved;
}

}  // namespace fracref::coarse_detail
