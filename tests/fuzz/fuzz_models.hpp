#pragma once
// Small fixed models the fuzz harnesses apply fuzzed data to.
#include "coarse/coarse_model.hpp"

namespace fracref::fuzz {

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
