#pragma once
// Small fixed models the fuzz harnesses apply fuzzed data to.
#include "coarse/coarse_model.hpp"
#include "io/mesh_soup.hpp"

namespace fracref::fuzz {

/// The closed, outward box [lo, hi] as 12 triangles.
inline MeshSoup box(const glm::dvec3& lo, const glm::dvec3& hi) {
  MeshSoup s;
  for (int k = 0; k < 8; ++k) s.positions.emplace_back(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2])});
    s.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[2]), std::uint32_t(q[3])});
  }
  return s;
}

/// Two unit cubes side by side along x, each split into 6 tets around its diagonal (Kuhn), the
/// left one labelled 0 and the right one 1: 12 vertices, 12 tets, two pieces.
inline TetMesh two_cubes() {
  TetMesh mesh;
  auto id = [](int i, int j, int k) { return std::uint32_t(i + 3 * (j + 2 * k)); };
  for (int k = 0; k <= 1; ++k)
    for (int j = 0; j <= 1; ++j)
      for (int i = 0; i <= 2; ++i) mesh.vertices.emplace_back(i, j, k);
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int i = 0; i < 2; ++i)
    for (const auto& p : perms) {
      glm::ivec3 c(i, 0, 0);
      glm::uvec4 tet;
      tet[0] = id(c.x, c.y, c.z);
      for (int s = 0; s < 2; ++s) {
        c[p[s]] += 1;
        tet[s + 1] = id(c.x, c.y, c.z);
      }
      tet[3] = id(i + 1, 1, 1);
      mesh.tets.push_back(tet);  // either orientation: build_tet_model reorients
      mesh.labels.push_back(i);
    }
  return mesh;
}

}  // namespace fracref::fuzz
