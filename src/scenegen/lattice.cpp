// The Kuhn lattice and the faces, edges and incidences of tet sets.
#include <algorithm>
#include <numeric>
#include <utility>

#include "coarse/tet_tables.hpp"
#include "scenegen/scenegen_internal.hpp"
#include "util/error.hpp"

namespace fracref::scenegen_detail {
namespace {

}  // namespace

glm::dvec3 tet_centroid(const TetSet& set, std::uint32_t t) {
  const glm::uvec4& k = set.tets[t];
  return 0.25 * (set.positions[k.x] + set.positions[k.y] + set.positions[k.z] + set.positions[k.w]);
}

VertexTets vertex_tets(const TetSet& set) {
  VertexTets vt;
  vt.offsets.assign(set.positions.size() + 1, 0);
  for (const glm::uvec4& t : set.tets)
    for (int c = 0; c < 4; ++c) ++vt.offsets[t[c] + 1];
  std::partial_sum(vt.offsets.begin(), vt.offsets.end(), vt.offsets.begin());
  vt.tets.resize(vt.offsets.back());
  std::vector<std::uint32_t> fill(vt.offsets.begin(), vt.offsets.end() - 1);
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (int c = 0; c < 4; ++c) vt.tets[fill[set.tets[t][c]]++] = t;
  return vt;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> surface_defects(const std::vector<glm::uvec3>& faces) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges, bad;
  for (const glm::uvec3& f : faces)
    for (int e = 0; e < 3; ++e) edges.push_back(std::minmax(f[e], f[(e + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0, j; i < edges.size(); i = j) {
    for (j = i + 1; j < edges.size() && edges[j] == edges[i];) ++j;
    if (j - i > 2) bad.push_back(edges[i]);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> around;  // (vertex, face)
  for (std::uint32_t f = 0; f < faces.size(); ++f)
    for (int c = 0; c < 3; ++c) around.push_back({faces[f][c], f});
  std::sort(around.begin(), around.end());
  std::vector<std::uint32_t> root;
  for (std::size_t i = 0, j; i < around.size(); i = j) {
    for (j = i + 1; j < around.size() && around[j].first == around[i].first;) ++j;
    // Fans around the vertex: its faces joined through a shared edge at it.
    root.resize(j - i);
    std::iota(root.begin(), root.end(), 0u);
    const auto find = [&root](std::uint32_t x) {
      while (root[x] != x) x = root[x] = root[root[x]];
      return x;
    };
    for (std::size_t a = i; a < j; ++a)
      for (std::size_t b = a + 1; b < j; ++b) {
        int shared = 0;
        for (int p = 0; p < 3; ++p)
          for (int q = 0; q < 3; ++q) shared += faces[around[a].second][p] == faces[around[b].second][q];
        if (shared >= 2) root[find(std::uint32_t(b - i))] = find(std::uint32_t(a - i));
      }
    std::size_t fans = 0;
    for (std::size_t a = 0; a < root.size(); ++a) fans += find(std::uint32_t(a)) == a;
    if (fans > 1) bad.push_back({around[i].first, around[i].first});
  }
  return bad;
}

TetFaces tet_faces(const TetSet& set) {
  struct Use {
    glm::uvec3 key;
    std::uint32_t tet;
    int local;
  };
  std::vector<Use> uses;
  uses.reserve(set.tets.size() * 4);
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    for (int l = 0; l < 4; ++l) {
      const glm::uvec4& k = set.tets[t];
      uses.push_back({sorted3({k[kTetFaces[l][0]], k[kTetFaces[l][1]], k[kTetFaces[l][2]]}), t, l});
    }
  std::sort(uses.begin(), uses.end(), [](const Use& a, const Use& b) {
    if (a.key != b.key) return less3(a.key, b.key);
    return a.tet != b.tet ? a.tet < b.tet : a.local < b.local;
  });
  TetFaces faces;
  for (std::size_t i = 0, j; i < uses.size(); i = j) {
    for (j = i + 1; j < uses.size() && uses[j].key == uses[i].key;) ++j;
    const glm::uvec4& k = set.tets[uses[i].tet];
    const int* l = kTetFaces[uses[i].local];
    const glm::uvec3 face(k[l[0]], k[l[1]], k[l[2]]);
    if (j - i == 1) {
      faces.hull.push_back(face);
      faces.hull_tet.push_back(uses[i].tet);
    } else if (j - i == 2) {
      faces.interior.push_back(face);
      faces.interior_tets.push_back({uses[i].tet, uses[i + 1].tet});
    } else {
      throw RunError("scenegen: a face is shared by more than two tets");
    }
  }
  return faces;
}

}  // namespace fracref::scenegen_detail
