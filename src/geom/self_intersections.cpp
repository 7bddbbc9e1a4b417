// find_self_intersections of intersect.hpp: AABB-tree broad phase, exact narrow phase.
#include <algorithm>
#include <string>

#include "geom/bvh.hpp"
#include "geom/intersect.hpp"
#include "geom/bvh_traverse.hpp"
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
  // One traversal of the tree against itself (nearby faces share descents), the exact tests in
  // its tasks; then sorted and truncated, so the answer does not depend on the threads.
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  std::vector<Pair> out = collect_overlaps<Pair>(tree, tree, true, options.threads,
                                                 [&](std::uint32_t i, std::uint32_t j, std::vector<Pair>& found) {
                                                   if (i >= options.query_faces) return;
                                                   if (mesh_faces_intersect(positions, triangles[i], triangles[j]))
                                                     found.emplace_back(i, j);
                                                 });
  std::sort(out.begin(), out.end());
  if (out.size() > options.max_report) out.resize(options.max_report);
  return out;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> find_self_intersections(
    const std::vector<glm::dvec3>& positions, const std::vector<TriangleIds>& triangles, std::size_t max_report) {
  SelfIntersectionOptions options;
  options.max_report = max_report;
  return find_self_intersections(positions, triangles, options);
}

}  // namespace fracref
