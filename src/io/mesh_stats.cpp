#include "io/mesh_stats.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include "io/mesh_writers.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::uint32_t> parent_;
};

void count_edges(const MeshSoup& soup, MeshStats& s) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(soup.triangles.size() * 3);
  for (const auto& t : soup.triangles)
    for (int i = 0; i < 3; ++i) edges.emplace_back(std::minmax(t[i], t[(i + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) ++s.boundary_edges;
    if (j - i >= 3) ++s.non_manifold_edges;
    i = j;
  }
}

// Per vertex, its incident triangles are joined when they share an edge through the vertex;
// more than one resulting fan makes the vertex non-manifold.
std::size_t count_non_manifold_vertices(const MeshSoup& soup) {
  const std::size_t n = soup.positions.size();
  std::vector<std::uint32_t> start(n + 1, 0);
  for (const auto& t : soup.triangles)
    for (std::uint32_t v : t) ++start[v + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::uint32_t> incident(start[n]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::uint32_t t = 0; t < soup.triangles.size(); ++t)
    for (std::uint32_t v : soup.triangles[t]) incident[fill[v]++] = t;

  std::size_t count = 0;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> spokes;  // (other vertex, local triangle)
  for (std::uint32_t v = 0; v < n; ++v) {
    const std::uint32_t k = start[v + 1] - start[v];
    if (k < 2) continue;
    spokes.clear();
    for (std::uint32_t local = 0; local < k; ++local)
      for (std::uint32_t w : soup.triangles[incident[start[v] + local]])
        if (w != v) spokes.emplace_back(w, local);
    std::sort(spokes.begin(), spokes.end());
    DisjointSets fans(k);
    for (std::size_t i = 1; i < spokes.size(); ++i)
      if (spokes[i].first == spokes[i - 1].first) fans.unite(spokes[i].second, spokes[i - 1].second);
    std::size_t roots = 0;
    for (std::uint32_t local = 0; local < k; ++local) roots += fans.find(local) == local;
    count += roots > 1;
  }
  return count;
}

std::size_t count_components(const MeshSoup& soup) {
  DisjointSets sets(soup.positions.size());
  std::vector<bool> used(soup.positions.size(), false);
  for (const auto& t : soup.triangles) {
    sets.unite(t[0], t[1]);
    sets.unite(t[1], t[2]);
    for (std::uint32_t v : t) used[v] = true;
  }
  std::size_t components = 0;
  for (std::uint32_t v = 0; v < soup.positions.size(); ++v) components += used[v] && sets.find(v) == v;
  return components;
}

}  // namespace

MeshStats mesh_stats(const MeshSoup& soup) {
  for (std::size_t t = 0; t < soup.triangles.size(); ++t)
    for (std::uint32_t v : soup.triangles[t])
      if (v >= soup.positions.size())
        throw RunError("mesh_stats: triangle " + std::to_string(t) + " references vertex " + std::to_string(v) +
                       " of " + std::to_string(soup.positions.size()));
  MeshStats s;
  s.vertices = soup.positions.size();
  s.faces = soup.triangles.size();
  s.polygons_triangulated = soup.polygons_triangulated;
  if (!soup.positions.empty()) {
    s.bbox_min = s.bbox_max = soup.positions[0];
    for (const glm::dvec3& p : soup.positions) {
      s.bbox_min = glm::min(s.bbox_min, p);
      s.bbox_max = glm::max(s.bbox_max, p);
    }
  }
  count_edges(soup, s);
  s.non_manifold_vertices = count_non_manifold_vertices(soup);
  s.components = count_components(soup);
  s.closed = s.boundary_edges == 0 && s.non_manifold_edges == 0 && s.faces > 0;
  return s;
}

namespace {
std::string json_vec3(const glm::dvec3& v) {
  std::string out = "[";
  for (int i = 0; i < 3; ++i) {
    if (i > 0) out += ", ";
    if (std::isfinite(v[i])) io_detail::append_double(out, v[i]);
    else out += "null";
  }
  return out + "]";
}
}  // namespace

std::string mesh_stats_json(const MeshStats& s) {
  auto field = [](const char* key, std::size_t value) { return std::string("\"") + key + "\": " + std::to_string(value) + ", "; };
  std::string out = "{";
  out += field("vertices", s.vertices);
  out += field("faces", s.faces);
  out += field("boundary_edges", s.boundary_edges);
  out += field("non_manifold_edges", s.non_manifold_edges);
  out += field("non_manifold_vertices", s.non_manifold_vertices);
  out += field("components", s.components);
  out += std::string("\"closed\": ") + (s.closed ? "true" : "false") + ", ";
  out += "\"bbox\": {\"min\": " + json_vec3(s.bbox_min) + ", \"max\": " + json_vec3(s.bbox_max) + "}, ";
  out += "\"polygons_triangulated\": " + std::to_string(s.polygons_triangulated) + "}";
  return out;
}

}  // namespace fracref
