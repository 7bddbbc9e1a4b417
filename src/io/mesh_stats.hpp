#pragma once
// Topology and extent of a triangle soup: what `fracref info` reports about an input mesh.
#include <cstddef>
#include <string>

#include <glm/glm.hpp>

#include "io/mesh_soup.hpp"

namespace fracref {

/// Counts describing a triangle soup. Edges are undirected vertex pairs.
struct MeshStats {
  std::size_t vertices = 0;               ///< positions, used or not
  std::size_t faces = 0;                  ///< triangles
  std::size_t boundary_edges = 0;         ///< edges used by exactly 1 triangle
  std::size_t non_manifold_edges = 0;     ///< edges used by 3 or more triangles
  std::size_t non_manifold_vertices = 0;  ///< vertices whose incident triangles form > 1 fan
  std::size_t components = 0;             ///< triangles connected through shared vertices
  glm::dvec3 bbox_min{0.0};               ///< over all positions; (0,0,0) when there are none
  glm::dvec3 bbox_max{0.0};
  bool closed = false;  ///< no boundary edge, no non-manifold edge, at least one face
  std::size_t polygons_triangulated = 0;  ///< copied from the soup
};

/// Computes the statistics of `soup`. A fan around a vertex is a maximal set of its incident
/// triangles connected through edges that contain the vertex; a vertex with more than one fan
/// (two cones touching at a tip, a bow tie) is non-manifold. Isolated unused vertices are not
/// components. Deterministic and O(T log T).
/// \pre every triangle index < soup.positions.size().
/// \throw RunError when a triangle index is out of range.
MeshStats mesh_stats(const MeshSoup& soup);

/// `stats` as one JSON object with keys vertices, faces, boundary_edges, non_manifold_edges,
/// non_manifold_vertices, components, closed, bbox {min:[x,y,z], max:[x,y,z]} and
/// polygons_triangulated (coordinates with 17 significant digits).
std::string mesh_stats_json(const MeshStats& stats);

}  // namespace fracref
