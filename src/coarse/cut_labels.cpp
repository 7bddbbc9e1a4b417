// Tet labellings for the cuts input: components of a crack set, and the fan clean-up
// (cut_labels.hpp).
#include "coarse/cut_labels.hpp"

#include <algorithm>
#include <array>
#include <numeric>
#include <utility>

#include "util/error.hpp"

namespace fracref {
namespace {

// The tets around every edge of the mesh, in fan order (CSR over the sorted edges).
struct EdgeFans {
  std::vector<glm::uvec2> edges;
  std::vector<std::uint32_t> offsets{0}, tets;
  std::vector<std::uint8_t> path;  // 1: the fan runs from hull face to hull face (a hull edge)
};

// The two corners of tet t other than edge (a, b).
std::array<std::uint32_t, 2> others(const glm::uvec4& t, std::uint32_t a, std::uint32_t b) {
  std::array<std::uint32_t, 2> o{0, 0};
  int n = 0;
  for (int i = 0; i < 4; ++i)
    if (t[i] != a && t[i] != b && n < 2) o[n++] = t[i];
  return o;
}

// Orders `group` (the tets at edge (a, b)) so that consecutive tets share a face. Two tets share
// a face at the edge when they share one of their other corners; a corner used by one tet only
// is a hull face, where a path starts. Returns true for a path.
bool order_fan(const TetSet& set, std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>& group) {
  const std::size_t n = group.size();
  std::vector<std::array<std::uint32_t, 2>> o(n);
  for (std::size_t i = 0; i < n; ++i) o[i] = others(set.tets[group[i]], a, b);
  auto uses = [&](std::uint32_t v) {
    int c = 0;
    for (const auto& x : o) c += (x[0] == v) + (x[1] == v);
    return c;
  };
  // Start: the lowest tet with a hull face at the edge, leaving through its other corner; for a
  // cycle, the lowest tet, leaving through its lower other corner.
  std::size_t start = 0;
  std::uint32_t exit = std::min(o[0][0], o[0][1]);
  bool path = false;
  for (std::size_t i = 0; i < n && !path; ++i)
    for (int k = 0; k < 2; ++k)
      if (uses(o[i][k]) == 1) {
        start = i, exit = o[i][1 - k], path = true;
        break;
      }
  std::vector<std::uint32_t> ordered{group[start]};
  std::vector<std::uint8_t> taken(n, 0);
  taken[start] = 1;
  for (std::size_t step = 1; step < n; ++step) {
    std::size_t next = n;
    for (std::size_t i = 0; i < n && next == n; ++i)
      if (!taken[i] && (o[i][0] == exit || o[i][1] == exit)) next = i;
    if (next == n) break;  // not a manifold fan (cannot happen for a conforming mesh)
    taken[next] = 1;
    ordered.push_back(group[next]);
    exit = o[next][0] == exit ? o[next][1] : o[next][0];
  }
  group = std::move(ordered);
  return path;
}

EdgeFans edge_fans(const TetSet& set) {
  std::vector<std::pair<glm::uvec2, std::uint32_t>> uses;
  uses.reserve(set.tets.size() * 6);
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const std::uint32_t a = set.tets[t][i], b = set.tets[t][j];
        uses.push_back({glm::uvec2(std::min(a, b), std::max(a, b)), t});
      }
  std::sort(uses.begin(), uses.end(), [](const auto& x, const auto& y) {
    if (x.first.x != y.first.x) return x.first.x < y.first.x;
    if (x.first.y != y.first.y) return x.first.y < y.first.y;
    return x.second < y.second;
  });
  EdgeFans fans;
  std::vector<std::uint32_t> group;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    group.clear();
    for (; j < uses.size() && uses[j].first == uses[i].first; ++j) group.push_back(uses[j].second);
    const bool path = order_fan(set, uses[i].first.x, uses[i].first.y, group);
    fans.edges.push_back(uses[i].first);
    fans.tets.insert(fans.tets.end(), group.begin(), group.end());
    fans.offsets.push_back(std::uint32_t(fans.tets.size()));
    fans.path.push_back(path ? 1 : 0);
    i = j;
  }
  return fans;
}

struct Run {
  std::uint32_t label = 0;
  std::uint32_t begin = 0, end = 0;  // positions in the fan (end may wrap past the fan's size)
  double volume = 0.0;
};

// The wedges of a fan under `labels`; for a cycle the first run starts at a label change and
// the last one wraps around.
std::vector<Run> fan_runs(const std::uint32_t* fan, std::uint32_t n, bool path, const std::vector<std::uint32_t>& labels,
                          const std::vector<double>& volume) {
  std::uint32_t first = 0;
  if (!path)
    while (first < n && labels[fan[first]] == labels[fan[(first + n - 1) % n]]) ++first;
  if (first == n) first = 0;  // one label all round
  std::vector<Run> runs;
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t t = fan[(first + k) % n];
    if (runs.empty() || runs.back().label != labels[t]) runs.push_back({labels[t], first + k, first + k, 0.0});
    runs.back().end = first + k + 1;
    runs.back().volume += volume[t];
  }
  return runs;
}

// Whether label a ranks above label b: more volume at the start, ties to the lower label.
struct Rank {
  const std::vector<double>& volume;
  bool above(std::uint32_t a, std::uint32_t b) const {
    return volume[a] != volume[b] ? volume[a] > volume[b] : a < b;
  }
};

struct Move {
  int run = -1;            // -1: the fan is good
  std::uint32_t to = 0;    // the label it takes
};

// A path is bad with three runs or more, a cycle when a label holds two runs. The move: the
// smallest offending run (any run of a bad path; in a cycle a run whose label repeats or whose
// neighbours share a label) that has a neighbour of a higher rank takes the label of its
// larger such neighbour. Labels only ever rise in rank, so the clean-up ends.
Move choose_move(const std::vector<Run>& runs, bool path, const Rank& rank) {
  const std::size_t n = runs.size();
  bool bad = path ? n >= 3 : false;
  for (std::size_t k = 0; k < n && !path && !bad; ++k)
    for (std::size_t m = k + 1; m < n && !bad; ++m) bad = runs[m].label == runs[k].label;
  Move best;
  if (!bad) return best;
  for (std::size_t k = 0; k < n; ++k) {
    const bool has_prev = !path || k > 0, has_next = !path || k + 1 < n;
    const Run* prev = has_prev ? &runs[(k + n - 1) % n] : nullptr;
    const Run* next = has_next ? &runs[(k + 1) % n] : nullptr;
    if (!path) {
      bool repeated = false;
      for (std::size_t m = 0; m < n; ++m) repeated = repeated || (m != k && runs[m].label == runs[k].label);
      if (!repeated && prev->label != next->label) continue;
    }
    const Run* to = nullptr;
    for (const Run* r : {prev, next})
      if (r && rank.above(r->label, runs[k].label) && (!to || r->volume > to->volume)) to = r;
    if (!to) continue;
    if (best.run < 0 || runs[k].volume < runs[std::size_t(best.run)].volume) best = {int(k), to->label};
  }
  return best;
}

}  // namespace

std::vector<std::uint32_t> crack_components(const TetSet& set, const InteriorFaces& faces,
                                            const std::vector<std::uint8_t>& cracked) {
  if (cracked.size() != faces.faces.size()) throw RunError("crack_components: one flag per interior face expected");
  std::vector<std::uint32_t> root(set.tets.size());
  std::iota(root.begin(), root.end(), 0u);
  auto find = [&root](std::uint32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (std::size_t f = 0; f < faces.faces.size(); ++f) {
    if (cracked[f]) continue;
    const std::uint32_t a = find(faces.tets[f].x), b = find(faces.tets[f].y);
    root[std::max(a, b)] = std::min(a, b);
  }
  for (std::uint32_t t = 0; t < root.size(); ++t) root[t] = find(t);
  return root;
}

FanCleanupStats clean_label_fans(const TetSet& set, std::vector<std::uint32_t>& labels, const FanCleanupOptions& options) {
  if (labels.size() != set.tets.size()) throw RunError("clean_label_fans: one label per tet expected");
  const EdgeFans fans = edge_fans(set);
  std::vector<double> volume(set.tets.size()), label_volume(set.tets.size(), 0.0);
  for (std::uint32_t t = 0; t < set.tets.size(); ++t) {
    volume[t] = tet_volume(set, t);
    if (labels[t] >= label_volume.size()) throw RunError("clean_label_fans: a label is not a tet id");
    label_volume[labels[t]] += volume[t];
  }
  const Rank rank{label_volume};
  FanCleanupStats stats;
  while (stats.passes < options.max_passes) {
    ++stats.passes;
    bool changed = false;
    for (std::size_t e = 0; e < fans.edges.size(); ++e) {
      const std::uint32_t* fan = fans.tets.data() + fans.offsets[e];
      const std::uint32_t n = fans.offsets[e + 1] - fans.offsets[e];
      bool uniform = true;
      for (std::uint32_t k = 1; k < n && uniform; ++k) uniform = labels[fan[k]] == labels[fan[0]];
      if (uniform) continue;
      for (std::uint32_t guard = 0; guard < n; ++guard) {
        const std::vector<Run> runs = fan_runs(fan, n, fans.path[e] != 0, labels, volume);
        const Move move = choose_move(runs, fans.path[e] != 0, rank);
        if (move.run < 0) break;
        const std::size_t r = std::size_t(move.run);
        for (std::uint32_t p = runs[r].begin; p < runs[r].end; ++p) labels[fan[p % n]] = move.to;
        stats.tets_moved += runs[r].end - runs[r].begin;
        changed = true;
      }
    }
    if (!changed) {
      stats.clean = true;
      break;
    }
  }
  return stats;
}

}  // namespace fracref
