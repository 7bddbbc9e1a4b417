// Welding, keys and the assembly of S shared by the tet and pieces builders.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>

#include "coarse/coarse_internal.hpp"
#include "coarse/tet_tables.hpp"
#include "util/error.hpp"

namespace fracref::coarse_detail {
namespace {

struct CellEntry {
  std::int64_t x, y, z;
  std::uint32_t index;
  bool operator<(const CellEntry& o) const { return std::tie(x, y, z, index) < std::tie(o.x, o.y, o.z, o.index); }
};

bool within(const glm::dvec3& a, const glm::dvec3& b, double tolerance) {
  return std::abs(a.x - b.x) <= tolerance && std::abs(a.y - b.y) <= tolerance && std::abs(a.z - b.z) <= tolerance;
}

}  // namespace

double bbox_diagonal(const std::vector<glm::dvec3>& points) {
  if (points.empty()) return 0.0;
  glm::dvec3 lo = points[0], hi = points[0];
  for (const glm::dvec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

std::vector<std::uint32_t> weld_points(const std::vector<glm::dvec3>& points, double tolerance) {
  const std::size_t n = points.size();
  MinUnion sets(n);
  glm::dvec3 lo(0.0), hi(0.0);
  if (n) lo = hi = points[0];
  for (const glm::dvec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  // Cells no smaller than the tolerance, so welded points are at most one cell apart; and not so
  // small that the cell coordinates overflow.
  const double cell = std::max({tolerance, extent * 1e-15, std::numeric_limits<double>::min()});
  std::vector<CellEntry> cells(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const glm::dvec3 c = glm::floor((points[i] - lo) / cell);
    cells[i] = {std::int64_t(c.x), std::int64_t(c.y), std::int64_t(c.z), i};
  }
  std::vector<CellEntry> sorted = cells;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t i = 0; i < n; ++i) {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const CellEntry key{cells[i].x + dx, cells[i].y + dy, cells[i].z + dz, 0};
          for (auto it = std::lower_bound(sorted.begin(), sorted.end(), key);
               it != sorted.end() && it->x == key.x && it->y == key.y && it->z == key.z; ++it)
            if (it->index > i && within(points[i], points[it->index], tolerance)) sets.unite(i, it->index);
        }
  }
  std::vector<std::uint32_t> rep(n);
  for (std::uint32_t i = 0; i < n; ++i) rep[i] = sets.find(i);
  return rep;
}

std::string point_text(const glm::dvec3& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.9g, %.9g, %.9g)", p.x, p.y, p.z);
  return text;
}

glm::uvec3 sorted_key(glm::uvec3 t) { return sorted3(t); }

bool same_winding(const glm::uvec3& x, const glm::uvec3& y) {
  // Rotate y so it starts at x's first corner, then compare the second.
  if (y.x == x.x) return y.y == x.y;
  if (y.y == x.x) return y.z == x.y;
  return y.x == x.y;
}

namespace {

// Per copy of S (vertex s seen by piece p, in surface.copies order) the lowest model vertex p
// uses at s.
std::vector<std::uint32_t> copy_model_vertices(const FractureSurface& s, const std::vector<SurfaceFace>& faces,
                                               const std::vector<std::uint32_t>& to_surface) {
  std::vector<std::tuple<std::uint32_t, int, std::uint32_t>> uses;
  uses.reserve(faces.size() * 6);
  for (const SurfaceFace& f : faces)
    for (int i = 0; i < 3; ++i) {
      uses.emplace_back(to_surface[f.welded[i]], f.front, f.front_model[i]);
      uses.emplace_back(to_surface[f.welded[i]], f.back, f.back_model[i]);
    }
  std::sort(uses.begin(), uses.end());
  std::vector<std::uint32_t> out;
  out.reserve(s.copies.size());
  for (std::size_t i = 0; i < uses.size(); ++i) {
    const bool first = i == 0 || std::get<0>(uses[i]) != std::get<0>(uses[i - 1]) ||
                       std::get<1>(uses[i]) != std::get<1>(uses[i - 1]);
    if (first) out.push_back(std::get<2>(uses[i]));
  }
  if (out.size() != s.copies.size()) throw RunError("coarse model: copies of S do not match the pieces' corners");
  return out;
}

}  // namespace

void assemble_surface(CoarseModel& model, const std::vector<SurfaceFace>& faces, const std::string& source) {
  std::vector<std::uint32_t> used;
  used.reserve(faces.size() * 3);
  for (const SurfaceFace& f : faces) used.insert(used.end(), {f.welded.x, f.welded.y, f.welded.z});
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<std::uint32_t> to_surface(model.vertices.size(), std::numeric_limits<std::uint32_t>::max());
  std::vector<glm::vec4> positions(used.size());
  for (std::uint32_t i = 0; i < used.size(); ++i) {
    to_surface[used[i]] = i;
    positions[i] = glm::vec4(glm::vec3(model.vertices[used[i]]), 1.0f);
  }
  std::vector<glm::uvec4> tris(faces.size());
  std::vector<glm::ivec2> pieces(faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const glm::uvec3 w = faces[f].welded;
    tris[f] = glm::uvec4(to_surface[w.x], to_surface[w.y], to_surface[w.z], 0u);
    pieces[f] = glm::ivec2(faces[f].front, faces[f].back);
  }
  try {
    model.surface = make_fracture_surface(std::move(positions), std::move(tris), std::move(pieces), model.piece_count);
  } catch (const InputError& e) {
    throw InvalidSurfaceError(source + ": the coarse fracture surface is invalid: " + e.what());
  }
  const std::string broken = validate(model.surface);
  if (!broken.empty()) throw InvalidSurfaceError(source + ": the coarse fracture surface is invalid: " + broken);
  model.surface_to_model_vertex = std::move(used);
  model.surface_copy_model_vertex = copy_model_vertices(model.surface, faces, to_surface);
}

}  // namespace fracref::coarse_detail
