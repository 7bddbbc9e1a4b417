#pragma once
// What the CLI tests measure on the surfaces a run writes.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "io/mesh_io.hpp"

namespace cli_test {

// The edges between two faces of the surface in `ply` that bend past 120 degrees: folds and
// creases, which the flow's smoothing does not make on its own.
inline std::size_t creases(const std::filesystem::path& ply) {
  const fracref::MeshSoup m = fracref::read_ply(ply);
  std::vector<glm::dvec3> normal;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::pair<std::size_t, bool>>> edges;
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const auto& t = m.triangles[f];
    normal.push_back(glm::normalize(glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]])));
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back({f, a < b});
    }
  }
  std::size_t n = 0;
  for (const auto& [e, faces] : edges) {
    if (faces.size() != 2) continue;  // on the rim or a junction
    const double sign = faces[0].second != faces[1].second ? 1.0 : -1.0;  // as oriented alike
    n += sign * glm::dot(normal[faces[0].first], normal[faces[1].first]) < std::cos(120.0 * M_PI / 180.0);
  }
  return n;
}

}  // namespace cli_test
