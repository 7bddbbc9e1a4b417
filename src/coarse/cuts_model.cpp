#include "coarse/cuts_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "coarse/tet_lattice.hpp"
#include "geom/bvh.hpp"
#include "io/mesh_io.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {


// Does the segment p→q cross triangle (a, b, c)? Möller–Trumbore, ends included.
bool segment_hits(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 d = q - p, e1 = b - a, e2 = c - a, h = glm::cross(d, e2);
  const double det = glm::dot(e1, h);
  if (det == 0.0) return false;
  const glm::dvec3 s = p - a, k = glm::cross(s, e1);
  const double u = glm::dot(s, h) / det, v = glm::dot(d, k) / det, t = glm::dot(e2, k) / det;
  return u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t >= 0.0 && t <= 1.0;
}

// Per triangle of `cuts`, its connected part (triangles sharing a vertex), numbered by lowest triangle.
std::vector<std::uint32_t> cut_parts(const MeshSoup& cuts, std::uint32_t& count) {
  std::vector<std::uint32_t> root(cuts.positions.size());
  std::iota(root.begin(), root.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (const auto& t : cuts.triangles)
    for (int i = 1; i < 3; ++i) {
      const std::uint32_t a = find(t[0]), b = find(t[i]);
      root[std::max(a, b)] = std::min(a, b);
    }
  std::vector<std::uint32_t> id(cuts.positions.size(), 0xffffffffu), part;
  count = 0;
  for (const auto& t : cuts.triangles) {
    std::uint32_t& r = id[find(t[0])];
    if (r == 0xffffffffu) r = count++;
    part.push_back(r);
  }
  return part;
}

std::string near_text(const glm::dvec3& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", p.x, p.y, p.z);
  return buf;
}

}  // namespace

CoarseModel build_cuts_model(const MeshSoup& exterior, const MeshSoup& cuts, const std::string& cuts_file,
                             const CutsOptions& options) {
  if (cuts.triangles.empty()) throw InputError(cuts_file + ": the cuts file has no face");
  const TetSet set = stuff_inside(exterior.positions, exterior.triangles, options.cells_per_diagonal, options.warp);
  const InteriorFaces faces = interior_faces(set);
  std::uint32_t parts = 0;
  const std::vector<std::uint32_t> part = cut_parts(cuts, parts);
  const Bvh bvh = build_bvh(cuts.positions, cuts.triangles);
  auto centroid = [&](std::uint32_t t) {
    const glm::uvec4& k = set.tets[t];
    return 0.25 * (set.positions[k.x] + set.positions[k.y] + set.positions[k.z] + set.positions[k.w]);
  };
  CrackList cracks;
  cracks.file = cuts_file;
  std::vector<std::uint8_t> crossed(parts, 0);
  std::vector<std::uint32_t> hits;
  for (std::size_t f = 0; f < faces.faces.size(); ++f) {
    const glm::dvec3 p = centroid(faces.tets[f].x), q = centroid(faces.tets[f].y);
    Aabb box;
    box.expand(p);
    box.expand(q);
    hits.clear();
    query_box(bvh, box, hits);
    bool cracked = false;
    for (const std::uint32_t t : hits) {
      const auto& tri = cuts.triangles[t];
      if (!segment_hits(p, q, cuts.positions[tri[0]], cuts.positions[tri[1]], cuts.positions[tri[2]])) continue;
      crossed[part[t]] = 1;
      cracked = true;
    }
    if (cracked) cracks.faces.push_back(faces.faces[f]);
  }
  for (std::uint32_t c = 0; c < parts; ++c) {
    if (crossed[c]) continue;
    const std::uint32_t t = std::uint32_t(std::find(part.begin(), part.end(), c) - part.begin());
    throw InputError(cuts_file + ": cut " + std::to_string(c + 1) + " of " + std::to_string(parts) + " (face " +
                     std::to_string((cuts.triangle_polygon.empty() ? t : cuts.triangle_polygon[t]) + 1) + ", near " +
                     near_text(cuts.positions[cuts.triangles[t][0]]) +
                     ") crosses no tet face inside the exterior: it lies outside the exterior or is smaller than the lattice cell");
  }
  TetMesh mesh;
  mesh.file = cuts_file;
  mesh.vertices = set.positions;
  mesh.tets = set.tets;
  mesh.labels.assign(set.tets.size(), 0);
  TetModelOptions to;
  to.virtual_fracture = options.virtual_fracture;
  return build_tet_model(mesh, &cracks, to);
}

CoarseModel load_cuts_model(const std::filesystem::path& exterior, const std::filesystem::path& cuts,
                            const CutsOptions& options) {
  return build_cuts_model(read_mesh(exterior), read_mesh(cuts), cuts.string(), options);
}

}  // namespace fracref
