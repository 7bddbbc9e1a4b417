// find_step_collisions_with_static of ccd.hpp: a moving mesh against a static one (the exterior
// B), whose trees are built once by prepare_static_ccd_mesh.
#include <string>

#include "geom/bvh_traverse.hpp"
#include "geom/ccd.hpp"
#include "geom/ccd_mesh_internal.hpp"
#include "util/error.hpp"
#include "util/parallel.hpp"

namespace fracref {

using namespace ccd_detail;

namespace {

// Leaves of 16 in every tree of the search against B: shallower trees build faster, and the
// step searches, dominated by the broad phase, traverse fewer nodes. The pairs found are
// sorted, so the trees' shape does not show in the results.
constexpr std::uint32_t kStaticLeaf = 16;

}  // namespace

StaticCcdMesh prepare_static_ccd_mesh(const std::vector<dvec3>& positions, const Tris& triangles, double min_distance,
                                      int threads) {
  check_positions(positions, "static");
  check_triangles(triangles, positions.size(), "static");
  StaticCcdMesh m;
  m.positions = positions;
  m.triangles = triangles;
  m.min_distance = min_distance;
  const double grow = std::max(0.0, min_distance);
  BvhOptions tree_options;
  tree_options.leaf_size = kStaticLeaf;
  tree_options.threads = threads;
  m.vertices = used_vertices(triangles, positions.size());
  m.edges = unique_edges(triangles);
  m.triangle_tree = build_bvh(swept_boxes(positions, positions, triangles, grow), tree_options);
  m.vertex_tree = build_bvh(swept_boxes(positions, positions, m.vertices, grow), tree_options);
  m.edge_tree = build_bvh(swept_boxes(positions, positions, m.edges, grow), tree_options);
  return m;
}

std::vector<CcdPair> find_step_collisions_with_static(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1,
                                                      const Tris& triangles, const std::vector<dvec3>& static_positions,
                                                      const Tris& static_triangles, const StepCcdOptions& options) {
  const StaticCcdMesh prepared =
      prepare_static_ccd_mesh(static_positions, static_triangles, options.ccd.min_distance, options.threads);
  return find_step_collisions_with_static(x0, x1, triangles, prepared, options);
}

std::vector<CcdPair> find_step_collisions_with_static(const std::vector<dvec3>& x0, const std::vector<dvec3>& x1,
                                                      const Tris& triangles, const StaticCcdMesh& m,
                                                      const StepCcdOptions& options) {
  if (x0.size() != x1.size())
    throw InputError("step collisions: " + std::to_string(x0.size()) + " start positions but " +
                     std::to_string(x1.size()) + " end positions");
  check_positions(x0, "start");
  check_positions(x1, "end");
  check_triangles(triangles, x0.size(), "moving");
  const CcdOptions& ccd = options.ccd;
  BvhOptions tree_options;
  tree_options.leaf_size = kStaticLeaf;
  tree_options.threads = options.threads;
  const auto& s = m.positions;
  const Tris& static_triangles = m.triangles;
  check_flags(options.ignored_vertices, x0.size(), "ignored-vertex");
  check_flags(options.active_vertices, x0.size(), "active-vertex");
  // Elements with an ignored vertex, or without an active one, take part in no pair.
  std::vector<std::uint8_t> take(x0.size(), 0);  // 0: no, 1: yes if not ignored, 2: ignored
  parallel_chunks(x0.size(), chunk_count(x0.size(), 8192), options.threads,
                  [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t v = begin; v < end; ++v)
                      take[v] = (options.ignored_vertices && (*options.ignored_vertices)[v])
                                    ? 2
                                    : (is_active(x0, x1, options, v) ? 1 : 0);
                  });
  auto keep = [&](auto ids) {
    bool any = false;
    for (std::uint32_t v : ids) {
      if (take[v] == 2) return false;
      any = any || take[v] == 1;
    }
    return any;
  };
  std::vector<std::array<std::uint32_t, 1>> moving_vertices;
  for (const auto& v : used_vertices(triangles, x0.size()))
    if (keep(v)) moving_vertices.push_back(v);
  std::vector<std::uint32_t> moving_triangles;
  for (std::uint32_t t = 0; t < triangles.size(); ++t)
    if (keep(triangles[t])) moving_triangles.push_back(t);
  // An edge with a vertex that takes part lies only on triangles with such a vertex: the edges
  // are found among those (in later rounds a few), in the order of the whole mesh's edges.
  Tris touched;
  for (const auto& t : triangles)
    if (take[t[0]] == 1 || take[t[1]] == 1 || take[t[2]] == 1) touched.push_back(t);
  std::vector<Edge> edges;
  for (const Edge& e : unique_edges(touched))
    if (keep(e)) edges.push_back(e);
  const std::vector<double> r = travels(x0, x1, options.threads);
  // The three trees over the moving elements side by side, each on one thread.
  Bvh moving_vertex_tree, moving_tri_tree, moving_edge_tree;
  BvhOptions one = tree_options;
  one.threads = 1;
  parallel_chunks(3, 3, options.threads, [&](std::size_t k, std::size_t, std::size_t) {
    if (k == 0) moving_vertex_tree = build_bvh(swept_boxes(x0, x1, moving_vertices, 0.0), one);
    if (k == 1) {
      std::vector<Aabb> tri_boxes(moving_triangles.size());
      for (std::size_t i = 0; i < moving_triangles.size(); ++i)
        tri_boxes[i] = swept_box(x0, x1, triangles[moving_triangles[i]], 0.0);
      moving_tri_tree = build_bvh(tri_boxes, one);
    }
    if (k == 2) moving_edge_tree = build_bvh(swept_boxes(x0, x1, edges, 0.0), one);
  });
  // Moving vertices against static triangles.
  auto out = collect_overlaps<CcdPair, BoxTest::float_rounded>(
      moving_vertex_tree, m.triangle_tree, false, options.threads,
      [&](std::uint32_t k, std::uint32_t t, std::vector<CcdPair>& found) {
        const std::uint32_t v = moving_vertices[k][0];
        const auto& tri = static_triangles[t];
        const double travel[4] = {r[v], 0.0, 0.0, 0.0};
        if (ccd_vertex_triangle(x0[v], s[tri[0]], s[tri[1]], s[tri[2]], x1[v], s[tri[0]], s[tri[1]], s[tri[2]], travel, ccd))
          found.push_back(vertex_pair(CcdKind::vertex_triangle, v, tri, t));
      });
  // Static vertices against moving triangles.
  auto tv = collect_overlaps<CcdPair, BoxTest::float_rounded>(
      m.vertex_tree, moving_tri_tree, false, options.threads,
      [&](std::uint32_t k, std::uint32_t i, std::vector<CcdPair>& found) {
        const std::uint32_t v = m.vertices[k][0], t = moving_triangles[i];
        const auto& tri = triangles[t];
        const double travel[4] = {0.0, r[tri[0]], r[tri[1]], r[tri[2]]};
        if (ccd_vertex_triangle(s[v], x0[tri[0]], x0[tri[1]], x0[tri[2]], s[v], x1[tri[0]], x1[tri[1]], x1[tri[2]], travel,
                                ccd))
          found.push_back(vertex_pair(CcdKind::triangle_vertex, v, tri, t));
      });
  // Moving edges against static edges.
  auto ee = collect_overlaps<CcdPair, BoxTest::float_rounded>(
      moving_edge_tree, m.edge_tree, false, options.threads,
      [&](std::uint32_t i, std::uint32_t j, std::vector<CcdPair>& found) {
        const Edge& e = edges[i];
        const Edge& f = m.edges[j];
        const double travel[4] = {r[e[0]], r[e[1]], 0.0, 0.0};
        if (ccd_edge_edge(x0[e[0]], x0[e[1]], s[f[0]], s[f[1]], x1[e[0]], x1[e[1]], s[f[0]], s[f[1]], travel, ccd))
          found.push_back({CcdKind::edge_edge, {e[0], e[1], f[0], f[1]}, CcdPair::kNoTriangle});
      });
  out.insert(out.end(), tv.begin(), tv.end());
  out.insert(out.end(), ee.begin(), ee.end());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace fracref
