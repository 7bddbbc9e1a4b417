#include "coarse/cuts_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include "coarse/coarse_internal.hpp"
#include "coarse/cut_extension.hpp"
#include "coarse/cut_labels.hpp"
#include "coarse/tet_lattice.hpp"
#include "coarse/tet_tables.hpp"
#include "coarse/virtual_fracture.hpp"
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

TetSet stuff_exterior(const MeshSoup& exterior, double cells_per_diagonal, const CutsOptions& o) {
  return stuff_inside(exterior.positions, exterior.triangles, cells_per_diagonal, o.warp);
}

std::string cells_text(double cells) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", cells);
  return buf;
}

std::string near_text(const glm::dvec3& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", p.x, p.y, p.z);
  return buf;
}

constexpr std::uint32_t kNoCut = 0xffffffffu;

// Per interior face, 1 when the segment between the centroids of its two tets crosses a cut
// triangle; face_cut gets the lowest cut (connected part, `part` of each triangle) crossing
// each face, or kNoCut; `missed` is set to the first cut that cracks no face, or to `parts`.
std::vector<std::uint8_t> crack_faces(const TetSet& set, const InteriorFaces& faces, const MeshSoup& cuts,
                                      const std::vector<std::uint32_t>& part, std::uint32_t parts,
                                      std::vector<std::uint32_t>& face_cut, std::uint32_t& missed) {
  const Bvh bvh = build_bvh(cuts.positions, cuts.triangles);
  auto centroid = [&](std::uint32_t t) {
    const glm::uvec4& k = set.tets[t];
    return 0.25 * (set.positions[k.x] + set.positions[k.y] + set.positions[k.z] + set.positions[k.w]);
  };
  std::vector<std::uint8_t> cracked(faces.faces.size(), 0), crossed(parts, 0);
  face_cut.assign(faces.faces.size(), kNoCut);
  std::vector<std::uint32_t> hits;
  for (std::size_t f = 0; f < faces.faces.size(); ++f) {
    const glm::dvec3 p = centroid(faces.tets[f].x), q = centroid(faces.tets[f].y);
    Aabb box;
    box.expand(p);
    box.expand(q);
    hits.clear();
    query_box(bvh, box, hits);
    for (const std::uint32_t t : hits) {
      const auto& tri = cuts.triangles[t];
      if (!segment_hits(p, q, cuts.positions[tri[0]], cuts.positions[tri[1]], cuts.positions[tri[2]])) continue;
      crossed[part[t]] = 1;
      cracked[f] = 1;
      face_cut[f] = std::min(face_cut[f], part[t]);
    }
  }
  missed = std::uint32_t(std::find(crossed.begin(), crossed.end(), 0) - crossed.begin());
  return cracked;
}

// The error for cut c (0-based), which cracks no face at `cells` cells per diagonal (0: its
// bounding box misses the exterior's).
InputError missed_cut(const MeshSoup& cuts, const std::string& cuts_file, const std::vector<std::uint32_t>& part,
                      std::uint32_t parts, std::uint32_t c, double cells) {
  const std::uint32_t t = std::uint32_t(std::find(part.begin(), part.end(), c) - part.begin());
  const std::string which = cuts_file + ": cut " + std::to_string(c + 1) + " of " + std::to_string(parts) + " (face " +
                            std::to_string((cuts.triangle_polygon.empty() ? t : cuts.triangle_polygon[t]) + 1) +
                            ", near " + near_text(cuts.positions[cuts.triangles[t][0]]) + ")";
  if (cells == 0.0) return InputError(which + " lies outside the exterior's bounding box");
  return InputError(which + " crosses no tet face inside the exterior at " + cells_text(cells) +
                    " cells per diagonal: it lies outside the exterior or is smaller than the lattice cell");
}

// The faces of one tet only (the hull), corners as in the tet.
std::vector<glm::uvec3> hull_faces(const TetSet& set) {
  std::vector<std::pair<glm::uvec3, glm::uvec3>> all;  // (sorted key, face)
  all.reserve(set.tets.size() * 4);
  for (const glm::uvec4& t : set.tets)
    for (const auto& f : kTetFaces) {
      const glm::uvec3 face(t[f[0]], t[f[1]], t[f[2]]);
      all.push_back({sorted3(face), face});
    }
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return less3(a.first, b.first); });
  std::vector<glm::uvec3> hull;
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i + 1;
    while (j < all.size() && all[j].first == all[i].first) ++j;
    if (j - i == 1) hull.push_back(all[i].second);
    i = j;
  }
  return hull;
}

}  // namespace

CoarseModel build_cuts_model(const MeshSoup& exterior, const MeshSoup& cuts, const std::string& cuts_file,
                             const CutsOptions& options) {
  if (cuts.triangles.empty()) throw InputError(cuts_file + ": the cuts file has no face");
  std::uint32_t parts = 0;
  const std::vector<std::uint32_t> part = cut_parts(cuts, parts);
  // A cut whose box misses B's is outside whatever the lattice: refused before any refinement.
  {
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const glm::dvec3& p : exterior.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    std::vector<std::uint8_t> overlaps(parts, 0);
    for (std::size_t t = 0; t < cuts.triangles.size(); ++t) {
      glm::dvec3 a = cuts.positions[cuts.triangles[t][0]], b = a;
      for (const std::uint32_t v : cuts.triangles[t]) a = glm::min(a, cuts.positions[v]), b = glm::max(b, cuts.positions[v]);
      if (glm::all(glm::lessThanEqual(a, hi)) && glm::all(glm::greaterThanEqual(b, lo))) overlaps[part[t]] = 1;
    }
    const std::uint32_t out = std::uint32_t(std::find(overlaps.begin(), overlaps.end(), 0) - overlaps.begin());
    if (out < parts) throw missed_cut(cuts, cuts_file, part, parts, out, 0.0);
  }
  const bool automatic = options.cells_per_diagonal <= 0.0;
  double cells = automatic ? options.auto_cells_first : options.cells_per_diagonal;
  TetSet set;
  InteriorFaces faces;
  std::vector<std::uint8_t> cracked;
  std::vector<std::uint32_t> face_cut;
  for (;;) {
    try {
      set = stuff_exterior(exterior, cells, options);
    } catch (const RunError&) {  // no lattice tet inside: B is thinner than the cell everywhere
      if (automatic && cells * 2.0 <= options.auto_cells_max) {
        cells *= 2.0;
        continue;
      }
      throw InputError(cuts_file + ": no lattice tet lies inside the exterior at " + cells_text(cells) +
                       " cells per diagonal (the exterior is thinner than the cell): raise fracture.cells_per_diagonal");
    }
    faces = interior_faces(set);
    std::uint32_t missed = parts;
    cracked = crack_faces(set, faces, cuts, part, parts, face_cut, missed);
    if (missed == parts) break;
    if (!automatic || cells * 2.0 > options.auto_cells_max) throw missed_cut(cuts, cuts_file, part, parts, missed, cells);
    cells *= 2.0;
  }
  std::size_t virtual_faces = 0;
  double virtual_area = 0.0;
  if (options.virtual_fracture) {
    // Flat cuts grow in their plane; what still ends inside B grows face by face.
    const PlaneExtensionStats pe = extend_in_planes(set, faces, cut_planes(cuts, part, parts), face_cut, cracked);
    const VirtualFractureStats vf = extend_cracks(set.positions, faces.faces, hull_faces(set), cracked);
    virtual_faces = pe.faces_added + vf.faces_added;
    virtual_area = pe.area_added + vf.area_added;
  }
  std::vector<std::uint32_t> labels = crack_components(set, faces, cracked);
  TetMesh mesh;
  mesh.file = cuts_file;
  mesh.vertices = set.positions;
  mesh.tets = set.tets;
  // Cracks inside one component separate nothing. Without virtual fracture that is the user's
  // to fix: build_tet_model() refuses them as for tets. With it, what is left are slits the
  // lattice made where a cut grazes B or a thin part (bounded by B and other cracks, so no
  // front grows them), and they are dropped; a cut none of whose faces separates goes around a
  // handle and is refused.
  CrackList residual;
  residual.file = cuts_file;
  std::vector<std::uint8_t> separates(parts, 0);
  for (std::size_t f = 0; f < faces.faces.size(); ++f) {
    const bool inside = labels[faces.tets[f].x] == labels[faces.tets[f].y];
    if (cracked[f] && inside) residual.faces.push_back(faces.faces[f]);
    if (face_cut[f] != kNoCut && !inside) separates[face_cut[f]] = 1;
  }
  if (!options.virtual_fracture && !residual.faces.empty()) {
    mesh.labels.assign(labels.begin(), labels.end());
    build_tet_model(mesh, &residual, TetModelOptions{.virtual_fracture = false});
  }
  for (std::uint32_t c = 0; c < parts; ++c)
    if (!separates[c])
      throw InputError(cuts_file + ": cut " + std::to_string(c + 1) + " of " + std::to_string(parts) +
                       " separates nothing even after virtual fracture (it goes around a handle of the exterior without cutting through it)");
  const FanCleanupStats fans = clean_label_fans(set, labels);
  mesh.labels.assign(labels.begin(), labels.end());
  TetModelOptions to;
  to.virtual_fracture = false;  // the labels separate by construction
  try {
    CoarseModel model = build_tet_model(mesh, nullptr, to);
    model.virtual_faces_added += virtual_faces;
    model.virtual_area_added += virtual_area;
    return model;
  } catch (const coarse_detail::InvalidSurfaceError& e) {
    // The tets are fracref's own: an invalid S is fracref's failure, not the input's.
    throw RunError(std::string("internal error in the cuts input: ") + e.what() + " (the lattice clean-up moved " +
                   std::to_string(fans.tets_moved) + " tets in " + std::to_string(fans.passes) + " passes" +
                   (fans.clean ? "" : " and left bad edges") + "; please report it with the scene)");
  }
}

CoarseModel load_cuts_model(const std::filesystem::path& exterior, const std::filesystem::path& cuts,
                            const CutsOptions& options) {
  return build_cuts_model(read_mesh(exterior), read_mesh(cuts), cuts.string(), options);
}

}  // namespace fracref
