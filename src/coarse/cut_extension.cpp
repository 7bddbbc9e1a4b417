// Flat cuts grown in their own plane (cut_extension.hpp).
#include "coarse/cut_extension.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <utility>

#include "util/error.hpp"

namespace fracref {
namespace {

// Interior faces around each edge (CSR over the sorted edges of the faces).
struct FaceEdgeTable {
  std::vector<glm::uvec2> edges;
  std::vector<std::uint32_t> offsets{0}, faces;

  explicit FaceEdgeTable(const InteriorFaces& f) {
    std::vector<std::pair<glm::uvec2, std::uint32_t>> uses;
    uses.reserve(f.faces.size() * 3);
    for (std::uint32_t i = 0; i < f.faces.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = f.faces[i][k], b = f.faces[i][(k + 1) % 3];
        uses.push_back({glm::uvec2(std::min(a, b), std::max(a, b)), i});
      }
    std::sort(uses.begin(), uses.end(), [](const auto& x, const auto& y) {
      if (x.first.x != y.first.x) return x.first.x < y.first.x;
      if (x.first.y != y.first.y) return x.first.y < y.first.y;
      return x.second < y.second;
    });
    for (std::size_t i = 0; i < uses.size(); ++i) {
      if (i > 0 && uses[i].first != uses[i - 1].first) offsets.push_back(std::uint32_t(i));
      if (i == 0 || uses[i].first != uses[i - 1].first) edges.push_back(uses[i].first);
      faces.push_back(uses[i].second);
    }
    offsets.push_back(std::uint32_t(uses.size()));
  }

  std::uint32_t find(std::uint32_t a, std::uint32_t b) const {
    const glm::uvec2 e(std::min(a, b), std::max(a, b));
    return std::uint32_t(std::lower_bound(edges.begin(), edges.end(), e, [](const glm::uvec2& x, const glm::uvec2& y) {
                           return x.x != y.x ? x.x < y.x : x.y < y.y;
                         }) -
                         edges.begin());
  }
};

}  // namespace

std::vector<CutPlane> cut_planes(const MeshSoup& cuts, const std::vector<std::uint32_t>& part, std::uint32_t parts,
                                 const PlaneOptions& options) {
  std::vector<CutPlane> planes(parts);
  std::vector<double> area(parts, 0.0);
  std::vector<glm::dvec3> first(parts, glm::dvec3(0.0));
  for (std::size_t t = 0; t < cuts.triangles.size(); ++t) {
    const auto& tri = cuts.triangles[t];
    const glm::dvec3 a = cuts.positions[tri[0]], b = cuts.positions[tri[1]], c = cuts.positions[tri[2]];
    const glm::dvec3 n = glm::cross(b - a, c - a);  // twice the area
    const double w = glm::length(n);
    if (w == 0.0) continue;
    const std::uint32_t p = part[t];
    if (first[p] == glm::dvec3(0.0)) first[p] = n;
    planes[p].normal += glm::dot(n, first[p]) < 0.0 ? -n : n;
    planes[p].point += w * (a + b + c) / 3.0;
    area[p] += w;
  }
  for (std::uint32_t p = 0; p < parts; ++p) {
    const double len = glm::length(planes[p].normal);
    if (area[p] == 0.0 || len == 0.0) continue;
    planes[p].point /= area[p];
    planes[p].normal /= len;
    planes[p].flat = true;
  }
  // Flatness: the farthest vertex from the plane against the cut's extent.
  std::vector<glm::dvec3> lo(parts, glm::dvec3(INFINITY)), hi(parts, glm::dvec3(-INFINITY));
  std::vector<double> off(parts, 0.0);
  for (std::size_t t = 0; t < cuts.triangles.size(); ++t)
    for (const std::uint32_t v : cuts.triangles[t]) {
      const std::uint32_t p = part[t];
      const glm::dvec3 x = cuts.positions[v];
      lo[p] = glm::min(lo[p], x), hi[p] = glm::max(hi[p], x);
      off[p] = std::max(off[p], std::abs(glm::dot(x - planes[p].point, planes[p].normal)));
    }
  for (std::uint32_t p = 0; p < parts; ++p)
    if (planes[p].flat && off[p] > options.flatness * glm::length(hi[p] - lo[p])) planes[p].flat = false;
  return planes;
}

PlaneExtensionStats extend_in_planes(const TetSet& set, const InteriorFaces& faces, const std::vector<CutPlane>& planes,
                                     const std::vector<std::uint32_t>& face_cut, std::vector<std::uint8_t>& cracked) {
  if (cracked.size() != faces.faces.size() || face_cut.size() != faces.faces.size())
    throw RunError("extend_in_planes: one entry per interior face expected");
  std::vector<glm::dvec3> centroid(set.tets.size());
  for (std::size_t t = 0; t < set.tets.size(); ++t) {
    const glm::uvec4& k = set.tets[t];
    centroid[t] = 0.25 * (set.positions[k.x] + set.positions[k.y] + set.positions[k.z] + set.positions[k.w]);
  }
  const FaceEdgeTable table(faces);
  std::vector<std::uint32_t> stamp(faces.faces.size(), 0);  // c + 1 once visited for cut c
  PlaneExtensionStats stats;
  std::deque<std::uint32_t> queue;
  for (std::uint32_t c = 0; c < planes.size(); ++c) {
    if (!planes[c].flat) continue;
    const CutPlane& pl = planes[c];
    auto crosses = [&](std::uint32_t f) {
      const double a = glm::dot(centroid[faces.tets[f].x] - pl.point, pl.normal);
      const double b = glm::dot(centroid[faces.tets[f].y] - pl.point, pl.normal);
      return (a <= 0.0) != (b <= 0.0);
    };
    for (std::uint32_t f = 0; f < faces.faces.size(); ++f)
      if (face_cut[f] == c) stamp[f] = c + 1, queue.push_back(f);
    while (!queue.empty()) {
      const std::uint32_t f = queue.front();
      queue.pop_front();
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t e = table.find(faces.faces[f][k], faces.faces[f][(k + 1) % 3]);
        for (std::uint32_t i = table.offsets[e]; i < table.offsets[e + 1]; ++i) {
          const std::uint32_t g = table.faces[i];
          if (stamp[g] == c + 1 || !crosses(g)) continue;
          stamp[g] = c + 1;
          queue.push_back(g);
          if (cracked[g]) continue;
          cracked[g] = 1;
          ++stats.faces_added;
          const glm::uvec3 q = faces.faces[g];
          stats.area_added += 0.5 * glm::length(glm::cross(set.positions[q.y] - set.positions[q.x],
                                                           set.positions[q.z] - set.positions[q.x]));
        }
      }
    }
  }
  return stats;
}

}  // namespace fracref
