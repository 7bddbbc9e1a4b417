#include "refine/motion_filters.hpp"

#include "util/parallel.hpp"

namespace fracref {
namespace {

// The unit tangent of the curve of `kind` edges (boundary or junction) through each vertex with
// exactly two of them; zero elsewhere, and with `hairpins_free` also where the curve turns back
// at the vertex (its two edges leave it less than 90 degrees apart). From the edges' directions
// away from the vertex, u1 and u2: the curve runs along u1 − u2 (their sum is its curvature's
// direction). Taken from the edges as stored instead, both could point away at a right angle (a
// lattice's junction corner, whose dot product is exactly 0), and the sum was taken for the
// tangent: the corner was then held along its curvature, could not round off, and turned into a
// hairpin as its neighbours moved on.
std::vector<glm::dvec3> curve_tangents(const FractureSurface& s, EdgeKind kind, bool hairpins_free) {
  std::vector<glm::dvec3> first(s.positions.size(), glm::dvec3(0.0)), tangent(s.positions.size(), glm::dvec3(0.0));
  std::vector<std::uint8_t> count(s.positions.size(), 0);
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    if (s.edge_special[e] != kind) continue;
    const glm::uvec2 ab = s.edges[e];
    glm::dvec3 dir = glm::dvec3(glm::vec3(s.positions[ab.y])) - glm::dvec3(glm::vec3(s.positions[ab.x]));
    const double len = glm::length(dir);
    if (len == 0.0) continue;
    dir /= len;
    for (std::uint32_t v : {ab.x, ab.y}) {
      const glm::dvec3 away = v == ab.x ? dir : -dir;
      if (count[v] < 255 && count[v]++ == 0) {
        first[v] = away;
      } else if (count[v] == 2) {
        tangent[v] = first[v] - away;
        if (hairpins_free && glm::dot(first[v], away) > 0.0) tangent[v] = glm::dvec3(0.0);
      }
    }
  }
  for (std::size_t v = 0; v < tangent.size(); ++v) {
    const double len = glm::length(tangent[v]);
    tangent[v] = (count[v] == 2 && len > 0.0) ? tangent[v] / len : glm::dvec3(0.0);
  }
  return tangent;
}

// Each vertex's unit normal, the area-weighted mean of its faces' normals; zero where they cancel.
std::vector<glm::dvec3> vertex_normals(const FractureSurface& s) {
  std::vector<glm::dvec3> n(s.positions.size(), glm::dvec3(0.0));
  for (const glm::uvec4& f : s.faces) {
    const glm::dvec3 a(glm::vec3(s.positions[f.x])), b(glm::vec3(s.positions[f.y])), c(glm::vec3(s.positions[f.z]));
    const glm::dvec3 twice_area_normal = glm::cross(b - a, c - a);
    n[f.x] += twice_area_normal, n[f.y] += twice_area_normal, n[f.z] += twice_area_normal;
  }
  for (glm::dvec3& v : n) {
    const double len = glm::length(v);
    v = len > 0.0 ? v / len : glm::dvec3(0.0);
  }
  return n;
}

glm::dmat3 onto_line(const glm::dvec3& u) { return glm::outerProduct(u, u); }
glm::dmat3 off_line(const glm::dvec3& u) { return glm::dmat3(1.0) - glm::outerProduct(u, u); }

}  // namespace

// The motions the flow allows each vertex (the implicit step's filter). A vertex inside a sheet
// moves freely: a sheet whose rim moves can only shrink if its vertices follow along it (held to
// their normals, a sheet lowers E far less). A vertex on B stays unless options.rim_motion: the
// pieces stage cannot yet cut B along a rim that wandered (its traces cross). With rim_motion a vertex on B slides on B across its rim curve
// (along the curve it would bunch the rim into slivers that no flip can repair, as boundary edges
// are special); one where the rim is not a simple curve slides on B freely. A junction vertex
// moves across its junction curve, and freely where the curve turns back at it: held across a
// hairpin's axis, its tip could not draw back, and it stayed behind as the sheets around it moved
// on, a spike on the pieces (the clay's hairs: junction angles of 3 to 18 degrees). Not so a
// sliding rim vertex where the rim turns back: freed to slide anywhere on B, the rim of the
// RefineLoop test's sheet no longer reached its valley (E fell by 4.5% instead of over 5%).
// Without options.tangential a sheet's vertex moves along its normal only. E's quadrature takes ψ
// at the corners, so in a valley of ψ narrower than the triangles E also falls when vertices
// slide along S into the valley without the surface moving: they bunch there, and the triangles
// between them become slivers that the flips (near-coplanar only) cannot mend. Held to their
// normals, they move the surface or stay (issue 28: the wall's brick-mortar interfaces).
std::vector<glm::dmat3> motion_filters(const FractureSurface& s, const ExteriorSurface& b, const MotionFilterOptions& o) {
  const std::vector<glm::dvec3> rim = curve_tangents(s, kEdgeBoundary, false),
                                junction = curve_tangents(s, kEdgeNonManifold, true);
  std::vector<glm::dmat3> out(s.positions.size(), glm::dmat3(1.0));
  const std::vector<glm::dvec3> normal = o.tangential ? std::vector<glm::dvec3>{} : vertex_normals(s);
  parallel_chunks(out.size(), chunk_count(out.size(), 4096), o.threads, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint32_t flags = s.vertex_flags[i];
      if ((flags & kVertexBoundary) && !o.rim_motion) {
        out[i] = glm::dmat3(0.0);
      } else if (flags & kVertexBoundary) {
        const glm::dvec3 nb = b.normal(closest_point(b.bvh, glm::dvec3(glm::vec3(s.positions[i]))).triangle);
        const glm::dvec3 across = glm::cross(nb, rim[i]);
        const double len = glm::length(across);
        out[i] = len > 0.5 ? onto_line(across / len) : off_line(nb);
      } else if ((flags & kVertexNonManifold) && junction[i] != glm::dvec3(0.0)) {
        out[i] = off_line(junction[i]);
      } else if (!o.tangential && !(flags & kVertexNonManifold) && normal[i] != glm::dvec3(0.0)) {
        out[i] = onto_line(normal[i]);
      }
    }
  });
  return out;
}

}  // namespace fracref
