// Exact intersections among the assembled triangles of the pieces, sorted into what a retry can
// fix (pieces.hpp, step 3c).
#include "geom/intersect.hpp"
#include "pieces/pieces_internal.hpp"

namespace fracref::pieces_detail {
namespace {

// Clashing pairs looked at per attempt; the next attempt finds the rest.
constexpr std::size_t kReportedClashes = 256;

}  // namespace

Clashes find_clashes(const std::vector<glm::dvec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& s_triangles,
                     const std::vector<std::array<std::uint32_t, 3>>& b_triangles, const std::vector<std::uint8_t>& on_b,
                     std::uint32_t s_vertex_count) {
  std::vector<TriangleIds> all(s_triangles.begin(), s_triangles.end());
  all.insert(all.end(), b_triangles.begin(), b_triangles.end());
  const std::uint32_t from_s = std::uint32_t(s_triangles.size());
  Clashes out;
  auto movable = [&](std::uint32_t t, auto&& visit) {
    if (t >= from_s) return;
    for (std::uint32_t v : all[t])
      if (v < s_vertex_count && !on_b[v]) visit(v);
  };
  // A fracture triangle through a B triangle is pushed along the B triangle's inward normal
  // (summed over the B triangles it crosses).
  auto inward = [&](std::uint32_t b) {
    const TriangleIds& t = all[b];
    const glm::dvec3 n = glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
    const double length = glm::length(n);
    return length > 0.0 ? -n / length : glm::dvec3(0.0);
  };
  // The cut B triangles tile B without overlaps by construction (and the final check of the
  // pieces tests everything): only pairs with a fracture triangle are looked for.
  SelfIntersectionOptions options;
  options.max_report = kReportedClashes;
  options.query_faces = from_s;
  for (const auto& [f, g] : find_self_intersections(positions, all, options)) {
    if (out.pairs == 0) out.first = {all[f], all[g]}, out.first_is_exterior = {f >= from_s, g >= from_s};
    ++out.pairs;
    if ((f >= from_s) == (g >= from_s)) {
      for (std::uint32_t t : {f, g}) movable(t, [&](std::uint32_t v) { out.folded.insert(v); });
      continue;
    }
    const std::uint32_t s_side = f < from_s ? f : g, b_side = f < from_s ? g : f;
    movable(s_side, [&](std::uint32_t v) { out.poking[v] += inward(b_side); });
  }
  for (auto& [v, d] : out.poking)
    if (const double length = glm::length(d); length > 0.0) d /= length;
  return out;
}

}  // namespace fracref::pieces_detail
