// Vertices duplicated where a crack opened, as a fracture simulator's last frame has them.
#include <algorithm>
#include <tuple>

#include "scenegen/scenegen_internal.hpp"

namespace fracref::scenegen_detail {

Duplication duplicate_vertices(TetSet& set, const std::vector<int>& tet_group, const std::vector<int>& group_split_frame,
                               const std::vector<std::uint8_t>& may_split) {
  const std::size_t n = set.positions.size();
  const VertexTets vt = vertex_tets(set);
  Duplication d;
  d.original_count = n;
  d.parent.resize(n);
  d.group.assign(n, -1);
  d.split_frame.assign(n, 0);
  std::vector<std::tuple<int, std::uint32_t, int>> copies;  // (split frame, original, group)
  for (std::uint32_t v = 0; v < n; ++v) {
    d.parent[v] = v;
    std::vector<int> groups;
    for (std::uint32_t i = vt.offsets[v]; i < vt.offsets[v + 1]; ++i) groups.push_back(tet_group[vt.tets[i]]);
    std::sort(groups.begin(), groups.end());
    groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
    if (groups.size() == 1) d.group[v] = groups[0];
    if (groups.size() < 2 || (!may_split.empty() && !may_split[v])) continue;
    int owner = groups[0];
    for (const int g : groups)
      if (group_split_frame[g] > group_split_frame[owner]) owner = g;
    d.group[v] = owner;
    for (const int g : groups)
      if (g != owner) copies.emplace_back(group_split_frame[g], v, g);
  }
  std::sort(copies.begin(), copies.end());
  std::vector<std::tuple<std::uint32_t, int, std::uint32_t>> lookup;  // (original, group, copy)
  for (const auto& [frame, v, g] : copies) {
    const std::uint32_t id = std::uint32_t(set.positions.size());
    set.positions.push_back(set.positions[v]);
    d.parent.push_back(v);
    d.group.push_back(g);
    d.split_frame.push_back(frame);
    lookup.emplace_back(v, g, id);
  }
  std::sort(lookup.begin(), lookup.end());
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (int c = 0; c < 4; ++c) {
      const auto it = std::lower_bound(lookup.begin(), lookup.end(), std::make_tuple(set.tets[t][c], tet_group[t], 0u));
      if (it != lookup.end() && std::get<0>(*it) == set.tets[t][c] && std::get<1>(*it) == tet_group[t])
        set.tets[t][c] = std::get<2>(*it);
    }
  return d;
}

}  // namespace fracref::scenegen_detail
