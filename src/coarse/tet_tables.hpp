#pragma once
// Small tables and keys shared by the tet code of the coarse room and the scene generator.
#include <utility>

#include <glm/glm.hpp>

namespace fracref {

/// Faces of a positively oriented tet (a, b, c, d), wound outward (the coarse loader's order).
inline constexpr int kTetFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

/// The six axis orders of the Kuhn triangulation of a cube; odd permutations are listed second.
inline constexpr int kKuhn[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};

/// The three ids in ascending order (a key for a face whatever its winding).
inline glm::uvec3 sorted3(glm::uvec3 k) {
  if (k.x > k.y) std::swap(k.x, k.y);
  if (k.y > k.z) std::swap(k.y, k.z);
  if (k.x > k.y) std::swap(k.x, k.y);
  return k;
}

/// Lexicographic order of triples.
inline bool less3(const glm::uvec3& a, const glm::uvec3& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

}  // namespace fracref
