// The coarse tetrahedral mesh of an exterior: a Kuhn lattice, kept by centroid, cleaned, snapped.
#include <algorithm>
#include <numeric>
#include <utility>

#include "geom/bvh.hpp"
#include "scenegen/scenegen_internal.hpp"
#include "util/error.hpp"

namespace fracref::scenegen_detail {
namespace {

// Faces of a positively oriented tet (a, b, c, d), wound outward (the coarse loader's order).
constexpr int kTetFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
// The six axis orders of the Kuhn triangulation; odd permutations are listed second.
constexpr int kKuhn[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};

glm::uvec3 sorted3(glm::uvec3 k) {
  if (k.x > k.y) std::swap(k.x, k.y);
  if (k.y > k.z) std::swap(k.y, k.z);
  if (k.x > k.y) std::swap(k.x, k.y);
  return k;
}

bool less3(const glm::uvec3& a, const glm::uvec3& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

}  // namespace

TetSet box_lattice(const LatticeSpec& spec) {
  TetSet set;
  const glm::ivec3 n = spec.cells;
  const auto id = [&](int i, int j, int k) { return std::uint32_t(i + (n.x + 1) * (j + (n.y + 1) * k)); };
  for (int k = 0; k <= n.z; ++k)
    for (int j = 0; j <= n.y; ++j)
      for (int i = 0; i <= n.x; ++i) {
        const glm::ivec3 g(i, j, k);
        glm::dvec3 p;
        for (int a = 0; a < 3; ++a)
          p[a] = g[a] == n[a] ? spec.hi[a] : spec.lo[a] + (spec.hi[a] - spec.lo[a]) * double(g[a]) / double(n[a]);
        set.positions.push_back(p);
      }
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i)
        for (int p = 0; p < 6; ++p) {
          glm::ivec3 g(i, j, k);
          glm::uvec4 t;
          t[0] = id(g.x, g.y, g.z);
          for (int s = 0; s < 3; ++s) {
            g[kKuhn[p][s]] += 1;
            t[s + 1] = id(g.x, g.y, g.z);
          }
          if (p >= 3) std::swap(t[2], t[3]);
          set.tets.push_back(t);
        }
  return set;
}

namespace {

// The hull of the kept tets, wound outward.
std::vector<glm::uvec3> kept_hull(const TetFaces& faces, const std::vector<std::uint8_t>& keep) {
  std::vector<glm::uvec3> hull;
  for (std::size_t i = 0; i < faces.interior.size(); ++i) {
    const bool a = keep[faces.interior_tets[i].x], b = keep[faces.interior_tets[i].y];
    if (a && !b) hull.push_back(faces.interior[i]);
    if (b && !a) hull.push_back({faces.interior[i].x, faces.interior[i].z, faces.interior[i].y});
  }
  for (std::size_t i = 0; i < faces.hull.size(); ++i)
    if (keep[faces.hull_tet[i]]) hull.push_back(faces.hull[i]);
  return hull;
}

// Keeps only the largest face-connected part of the kept tets (ties to the lowest tet).
void keep_largest_part(const TetFaces& faces, std::vector<std::uint8_t>& keep) {
  std::vector<std::uint32_t> root(keep.size());
  std::iota(root.begin(), root.end(), 0u);
  const auto find = [&root](std::uint32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (const glm::uvec2& t : faces.interior_tets)
    if (keep[t.x] && keep[t.y]) {
      const std::uint32_t a = find(t.x), b = find(t.y);
      root[std::max(a, b)] = std::min(a, b);
    }
  std::vector<std::size_t> size(keep.size(), 0);
  for (std::uint32_t t = 0; t < keep.size(); ++t)
    if (keep[t]) ++size[find(t)];
  const std::uint32_t best = std::uint32_t(std::max_element(size.begin(), size.end()) - size.begin());
  for (std::uint32_t t = 0; t < keep.size(); ++t)
    if (keep[t] && find(t) != best) keep[t] = 0;
}

// Adds every lattice tet around each defect until the kept set's hull is a 2-manifold.
void complete_defects(const TetSet& all, const TetFaces& faces, std::vector<std::uint8_t>& keep) {
  const VertexTets vt = vertex_tets(all);
  for (int round = 0; round < 50; ++round) {
    const auto bad = surface_defects(kept_hull(faces, keep));
    if (bad.empty()) return;
    for (const auto& [a, b] : bad)
      for (std::uint32_t i = vt.offsets[a]; i < vt.offsets[a + 1]; ++i) {
        const glm::uvec4& t = all.tets[vt.tets[i]];
        if (t.x == b || t.y == b || t.z == b || t.w == b) keep[vt.tets[i]] = 1;
      }
  }
  throw RunError("scenegen: the coarse lattice's hull did not become a 2-manifold");
}

TetSet compact(const TetSet& all, const std::vector<std::uint8_t>& keep) {
  std::vector<std::uint32_t> id(all.positions.size(), 0xffffffffu);
  TetSet out;
  for (std::uint32_t t = 0; t < all.tets.size(); ++t)
    if (keep[t])
      for (int c = 0; c < 4; ++c) id[all.tets[t][c]] = 0;
  for (std::uint32_t v = 0; v < all.positions.size(); ++v)
    if (id[v] == 0) {
      id[v] = std::uint32_t(out.positions.size());
      out.positions.push_back(all.positions[v]);
    }
  for (std::uint32_t t = 0; t < all.tets.size(); ++t)
    if (keep[t]) out.tets.push_back({id[all.tets[t].x], id[all.tets[t].y], id[all.tets[t].z], id[all.tets[t].w]});
  return out;
}

}  // namespace

glm::dvec3 tet_centroid(const TetSet& set, std::uint32_t t) {
  const glm::uvec4& k = set.tets[t];
  return 0.25 * (set.positions[k.x] + set.positions[k.y] + set.positions[k.z] + set.positions[k.w]);
}

double tet_volume(const TetSet& set, std::uint32_t t) {
  const glm::uvec4& k = set.tets[t];
  const glm::dvec3 a = set.positions[k.x];
  return glm::dot(set.positions[k.y] - a, glm::cross(set.positions[k.z] - a, set.positions[k.w] - a)) / 6.0;
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

TetSet lattice_tets(const TriMesh& exterior, const LatticeSpec& spec) {
  const TetSet all = box_lattice(spec);
  const TetFaces faces = tet_faces(all);
  const Bvh bvh = build_bvh(exterior.positions, exterior.triangles);
  std::vector<std::uint8_t> keep(all.tets.size(), 0);
  bool any = false;
  for (std::uint32_t t = 0; t < all.tets.size(); ++t) any |= (keep[t] = point_in_mesh(bvh, tet_centroid(all, t)));
  if (!any) throw RunError("scenegen: no lattice tet lies inside the exterior");
  keep_largest_part(faces, keep);
  complete_defects(all, faces, keep);
  keep_largest_part(faces, keep);
  TetSet set = compact(all, keep);
  std::vector<std::uint32_t> hull_vertices;
  for (const glm::uvec3& f : tet_faces(set).hull) hull_vertices.insert(hull_vertices.end(), {f.x, f.y, f.z});
  std::sort(hull_vertices.begin(), hull_vertices.end());
  hull_vertices.erase(std::unique(hull_vertices.begin(), hull_vertices.end()), hull_vertices.end());
  for (int pass = 0; pass < 4; ++pass) snap_to_exterior(set, bvh, hull_vertices, 0.2 * lattice_tet_volume(spec));
  return set;
}

double lattice_tet_volume(const LatticeSpec& spec) {
  const glm::dvec3 cell = (spec.hi - spec.lo) / glm::dvec3(spec.cells);
  return cell.x * cell.y * cell.z / 6.0;
}

void snap_to_exterior(TetSet& set, const Bvh& exterior, const std::vector<std::uint32_t>& vertices, double min_volume) {
  const VertexTets vt = vertex_tets(set);
  for (const std::uint32_t v : vertices) {
    const glm::dvec3 start = set.positions[v], target = closest_point(exterior, start).point;
    for (const double f : {1.0, 0.75, 0.5, 0.25}) {
      set.positions[v] = start + f * (target - start);
      bool ok = true;
      for (std::uint32_t i = vt.offsets[v]; i < vt.offsets[v + 1] && ok; ++i) ok = tet_volume(set, vt.tets[i]) >= min_volume;
      if (ok) break;
      set.positions[v] = start;
    }
  }
}

}  // namespace fracref::scenegen_detail
