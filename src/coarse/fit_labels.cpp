#include "coarse/fit_labels.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <utility>

#include "coarse/coarse_internal.hpp"
#include "coarse/cut_labels.hpp"
#include "coarse/tet_tables.hpp"

namespace fracref::coarse_detail {

std::vector<bool> deep_in_one_label(const TetSet& set, const std::vector<int>& label) {
  std::vector<std::pair<glm::uvec3, std::uint32_t>> faces;
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (const auto& f : kTetFaces) faces.emplace_back(sorted_key(glm::uvec3(set.tets[t][f[0]], set.tets[t][f[1]], set.tets[t][f[2]])), t);
  std::sort(faces.begin(), faces.end(), [](const auto& x, const auto& y) { return key_less(x.first, y.first); });
  constexpr int kMixed = -2, kNone = -1;
  std::vector<int> star(set.positions.size(), kNone);  // the one label around a vertex, or kMixed (on the hull too)
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].first == faces[i].first) ++j;
    if (j - i == 1)
      for (int k = 0; k < 3; ++k) star[faces[i].first[k]] = kMixed;
    i = j;
  }
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      int& s = star[set.tets[t][k]];
      s = s == kNone ? label[t] : (s == label[t] ? s : kMixed);
    }
  std::vector<bool> out(set.tets.size());
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    out[t] = star[set.tets[t].x] == label[t] && star[set.tets[t].y] == label[t] && star[set.tets[t].z] == label[t] &&
             star[set.tets[t].w] == label[t];
  return out;
}

std::size_t clean_fans(const TetSet& set, std::vector<int>& label) {
  std::vector<std::uint32_t> first(label.empty() ? 0 : std::size_t(*std::max_element(label.begin(), label.end())) + 1,
                                   UINT32_MAX);
  for (std::uint32_t t = 0; t < label.size(); ++t)
    if (first[label[t]] == UINT32_MAX) first[label[t]] = t;
  std::vector<std::uint32_t> ids(label.size());  // clean_label_fans() takes labels that are tet ids
  for (std::uint32_t t = 0; t < label.size(); ++t) ids[t] = first[label[t]];
  const FanCleanupStats stats = clean_label_fans(set, ids);
  const std::vector<int> before = label;
  for (std::uint32_t t = 0; t < label.size(); ++t) label[t] = before[ids[t]];
  return stats.tets_moved;
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

// Labels are read before the round and written after it, so the order of the tets does not
// matter.
std::size_t relabel_notches(std::size_t tets, const InteriorFaces& faces, std::vector<int>& label) {
  std::vector<std::array<int, 4>> around(tets);
  std::vector<std::uint8_t> count(tets, 0);
  for (const glm::uvec2& f : faces.tets) {
    if (count[f.x] < 4) around[f.x][count[f.x]++] = label[f.y];
    if (count[f.y] < 4) around[f.y][count[f.y]++] = label[f.x];
  }
  std::vector<int> next = label;
  std::size_t moved = 0;
  for (std::size_t t = 0; t < tets; ++t) {
    if (count[t] < 4) continue;  // on the hull
    for (int k = 0; k < 2; ++k) {
      const int other = around[t][std::size_t(k)];
      if (other == label[t]) continue;
      int same = 0;
      for (const int l : around[t]) same += l == other;
      if (same >= 3) {
        next[t] = other, ++moved;
        break;
      }
    }
  }
  label = std::move(next);
  return moved;
}

}  // namespace fracref::coarse_detail
