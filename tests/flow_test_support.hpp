#pragma once
// A field grid the flow tests share.
#include <vector>

#include "field/field_sampler.hpp"
#include "flow/velocity.hpp"

namespace fracref::test {

/// A field grid holding ψ(x) = c + g·x exactly (trilinear interpolation of a linear function is exact).
inline FieldGrid4 linear_field(float c, glm::vec3 g) {
  FieldGrid4 f;
  f.dims = {9, 9, 9};
  f.origin = glm::dvec3(-2.0);
  f.cell = 0.5;
  for (unsigned z = 0; z < 9; ++z)
    for (unsigned y = 0; y < 9; ++y)
      for (unsigned x = 0; x < 9; ++x) {
        const glm::vec3 p = glm::vec3(f.origin) + float(f.cell) * glm::vec3(x, y, z);
        f.values.push_back(glm::vec4(c + glm::dot(g, p), g));
      }
  return f;
}

/// The vertex -> faces CSR of `faces` over n vertices (faces ascending per vertex).
inline void vertex_face_csr(std::size_t n, const std::vector<glm::uvec4>& faces, std::vector<std::uint32_t>& offsets,
                            std::vector<std::uint32_t>& list) {
  offsets.assign(n + 1, 0);
  for (const glm::uvec4& f : faces)
    for (int k = 0; k < 3; ++k) ++offsets[f[k] + 1];
  for (std::size_t i = 0; i < n; ++i) offsets[i + 1] += offsets[i];
  list.assign(offsets.back(), 0);
  std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
  for (std::uint32_t j = 0; j < faces.size(); ++j)
    for (int k = 0; k < 3; ++k) list[fill[faces[j][k]]++] = j;
}

/// A triangle mesh as the flow kernels see it: flat arrays and the vertex -> faces CSR.
struct FlatMesh {
  std::vector<glm::vec4> positions;
  std::vector<glm::uvec4> faces;
  std::vector<std::uint32_t> vf_offsets, vf_faces;

  void build_csr() { vertex_face_csr(positions.size(), faces, vf_offsets, vf_faces); }
  SurfaceView view() const { return {positions, faces, vf_offsets, vf_faces}; }
};

}  // namespace fracref::test
