// find_self_intersections of intersect.hpp: AABB-tree broad phase, exact narrow phase.
#include <algorithm>
#include <string>

#include "geom/bvh.hpp"
#include "geom/intersect.hpp"
#include "geom/parallel.hpp"
#include "util/error.hpp"

namespace fracref {

std::vector<std::pair<std::uint32_t, std::uint32_t>> find_self_intersections(
    const std::vector<glm::dvec3>& positions, const std::vector<TriangleIds>& triangles,
    const SelfIntersectionOptions& options) {
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const TriangleIds& f = triangles[t];
    if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0])
      throw InputError("face " + std::to_string(t) + ": repeated vertex index " +
                       std::to_string(f[0] == f[1] || f[0] == f[2] ? f[0] : f[1]));
  }
  BvhOptions tree_options;
  tree_options.threads = options.threads;
  const Bvh tree = build_bvh(positions, triangles, tree_options);  // validates indices and coordinates
  const std::size_t n = std::min(triangles.size(), options.query_faces);
  const std::size_t chunks = geom_detail::chunk_count(n);
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> parts(chunks);
  geom_detail::parallel_chunks(n, chunks, options.threads, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::vector<std::uint32_t> hits;
    auto& found = parts[c];
    // A chunk never needs more than max_report pairs: earlier chunks come first in the output.
    for (std::size_t i = begin; i < end && found.size() < options.max_report; ++i) {
      hits.clear();
      Aabb box;
      for (std::uint32_t v : triangles[i]) box.expand(positions[v]);
      query_box(tree, box, hits);
      std::sort(hits.begin(), hits.end());
      for (std::uint32_t j : hits) {
        if (j <= i) continue;
        if (mesh_faces_intersect(positions, triangles[i], triangles[j])) {
          found.emplace_back(static_cast<std::uint32_t>(i), j);
          if (found.size() >= options.max_report) break;
        }
      }
    }
  });
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (auto& p : parts) {
    const std::size_t room = options.max_report - out.size();
    out.insert(out.end(), p.begin(), p.begin() + static_cast<std::ptrdiff_t>(std::min(room, p.size())));
    if (out.size() >= options.max_report) break;
  }
  return out;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> find_self_intersections(
    const std::vector<glm::dvec3>& positions, const std::vector<TriangleIds>& triangles, std::size_t max_report) {
  SelfIntersectionOptions options;
  options.max_report = max_report;
  return find_self_intersections(positions, triangles, options);
}

}  // namespace fracref
