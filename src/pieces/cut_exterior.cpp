// The cut of B along S's rim (pieces.hpp, step 2): every B triangle the rim touches is
// re-triangulated with the rim's segments as constraints.
#include <algorithm>
#include <set>

#include "geom/predicates.hpp"
#include "pieces/pieces_internal.hpp"
#include "util/error.hpp"

namespace fracref::pieces_detail {
namespace {

std::string edge_name(const ExteriorMesh& m, std::uint32_t e) {
  return std::to_string(m.edges[e].x) + "-" + std::to_string(m.edges[e].y);
}

void sort_edge_points(const ExteriorMesh& m, ExteriorCut& cut) {
  for (auto& [e, points] : cut.edge_points) {
    std::sort(points.begin(), points.end());
    for (std::size_t i = 1; i < points.size(); ++i)
      if (points[i].first == points[i - 1].first)
        throw RunError("exterior edge " + edge_name(m, e) + ": two rim points coincide at " +
                       format_point(cut.location[points[i].second].point));
  }
}

// A segment along a B edge must join neighbours on that edge: anything between them would be
// another trace touching this one.
void check_along_edge(const ExteriorMesh& m, const ExteriorCut& cut, std::uint32_t e, std::uint32_t a, std::uint32_t b) {
  std::vector<std::uint32_t> order{cut.b_vertex_gid[m.edges[e].x]};
  auto it = cut.edge_points.find(e);
  if (it != cut.edge_points.end())
    for (const auto& tp : it->second) order.push_back(tp.second);
  order.push_back(cut.b_vertex_gid[m.edges[e].y]);
  const auto ia = std::find(order.begin(), order.end(), a), ib = std::find(order.begin(), order.end(), b);
  if (ia == order.end() || ib == order.end() || std::abs(ia - ib) != 1)
    throw RunError("exterior edge " + edge_name(m, e) + ": a rim segment runs along it across another rim point");
}

using Constraints = std::map<std::uint32_t, std::vector<std::pair<std::uint32_t, std::uint32_t>>>;

Constraints classify_segments(const ExteriorMesh& m, const ExteriorCut& cut) {
  Constraints inside;
  for (const auto& seg : cut.segments) {
    const unsigned common = location_sides(m, cut.location[seg.from], seg.face) & location_sides(m, cut.location[seg.to], seg.face);
    if (common != 0) {
      const int k = (common & 1u) ? 0 : ((common & 2u) ? 1 : 2);
      check_along_edge(m, cut, m.face_edges[seg.face][k], seg.from, seg.to);
    } else {
      inside[seg.face].emplace_back(seg.from, seg.to);
    }
  }
  return inside;
}

class TriangleCutter {
 public:
  TriangleCutter(const ExteriorMesh& m, const ExteriorCut& cut, const std::vector<glm::dvec3>& positions, bool delaunay)
      : m_(m), cut_(cut), positions_(positions), delaunay_(delaunay) {}

  void cut(std::uint32_t f, const std::vector<std::pair<std::uint32_t, std::uint32_t>>* constraints,
           std::vector<std::array<std::uint32_t, 3>>& out) {
    input_ = CutTriangle{};
    input_.delaunay = delaunay_;
    gids_.clear();
    local_.clear();
    const auto& t = m_.triangles[f];
    add(cut_.b_vertex_gid[t[0]], {0.0, 0.0});
    add(cut_.b_vertex_gid[t[1]], {1.0, 0.0});
    add(cut_.b_vertex_gid[t[2]], {0.0, 1.0});
    for (int k = 0; k < 3; ++k) add_side(f, k);
    auto fp = cut_.face_points.find(f);
    if (fp != cut_.face_points.end())
      for (std::uint32_t g : fp->second) {
        const glm::dvec3& w = cut_.location[g].bary;
        input_.interior.push_back(add(g, {w.y, w.z}));
      }
    if (constraints)
      for (const auto& [a, b] : *constraints) {
        auto ia = local_.find(a), ib = local_.find(b);
        if (ia == local_.end() || ib == local_.end())
          throw RunError("internal: exterior triangle " + std::to_string(f) + ": a rim segment ends off the triangle");
        input_.constraints.emplace_back(ia->second, ib->second);
      }
    for (const auto& [ga, la] : local_)
      for (auto c = cut_.chords.lower_bound({ga, 0}); c != cut_.chords.end() && c->first == ga; ++c)
        if (auto lb = local_.find(c->second); lb != local_.end()) input_.avoid.emplace_back(la, lb->second);
    std::vector<std::array<std::uint32_t, 3>> tris;
    try {
      tris = triangulate_cut_triangle(input_);
    } catch (const RunError& e) {
      std::string names;
      for (const auto& seg : cut_.segments)
        if (seg.face == f) names += (names.empty() ? "" : ", ") + std::to_string(seg.from) + "-" + std::to_string(seg.to);
      throw RunError("internal: exterior triangle " + std::to_string(f) + " near " + format_point(m_.positions[t[0]]) +
                     " cannot be cut along the fracture surface's rim edges " + names + ": " + e.what());
    }
    for (const auto& tri : tris) out.push_back({gids_[tri[0]], gids_[tri[1]], gids_[tri[2]]});
  }

 private:
  std::uint32_t add(std::uint32_t gid, glm::dvec2 uv) {
    const std::uint32_t id = std::uint32_t(gids_.size());
    gids_.push_back(gid);
    local_[gid] = id;
    input_.uv.push_back(uv);
    input_.xyz.push_back(positions_[gid]);
    return id;
  }

  void add_side(std::uint32_t f, int k) {
    const std::uint32_t e = m_.face_edges[f][k];
    auto it = cut_.edge_points.find(e);
    if (it == cut_.edge_points.end()) return;
    const bool forward = m_.edges[e].x == m_.triangles[f][k];
    const auto& points = it->second;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const auto& [t, gid] = forward ? points[i] : points[points.size() - 1 - i];
      input_.side_points[k].push_back(add(gid, side_uv(k, forward, t)));
    }
  }

  const ExteriorMesh& m_;
  const ExteriorCut& cut_;
  const std::vector<glm::dvec3>& positions_;
  bool delaunay_;
  CutTriangle input_;
  std::vector<std::uint32_t> gids_;
  std::map<std::uint32_t, std::uint32_t> local_;
};

}  // namespace

std::vector<std::array<std::uint32_t, 3>> cut_exterior(const ExteriorMesh& m, ExteriorCut& cut,
                                                       const std::vector<glm::dvec3>& positions, bool delaunay) {
  sort_edge_points(m, cut);
  const Constraints inside = classify_segments(m, cut);
  std::set<std::uint32_t> touched;
  for (const auto& [f, c] : inside) touched.insert(f);
  for (const auto& [f, p] : cut.face_points) touched.insert(f);
  for (const auto& [e, p] : cut.edge_points) touched.insert(m.edge_faces[e].begin(), m.edge_faces[e].end());
  std::vector<std::array<std::uint32_t, 3>> out;
  out.reserve(m.triangles.size() + 4 * touched.size());
  TriangleCutter cutter(m, cut, positions, delaunay);
  for (std::uint32_t f = 0; f < m.triangles.size(); ++f) {
    const auto& t = m.triangles[f];
    if (!touched.count(f)) {
      out.push_back({cut.b_vertex_gid[t[0]], cut.b_vertex_gid[t[1]], cut.b_vertex_gid[t[2]]});
      continue;
    }
    auto it = inside.find(f);
    cutter.cut(f, it == inside.end() ? nullptr : &it->second, out);
  }
  return out;
}

}  // namespace fracref::pieces_detail
