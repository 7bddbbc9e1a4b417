// The non-conformity check of pre-fractured pieces: coplanar faces of different pieces whose
// interiors overlap without matching.
#include <algorithm>
#include <cmath>
#include <utility>

#include "coarse/coarse_internal.hpp"

namespace fracref::coarse_detail {
namespace {

struct Box {
  glm::dvec3 lo, hi;
};

Box face_box(const std::vector<glm::dvec3>& p, const glm::uvec3& f) {
  return {glm::min(p[f.x], glm::min(p[f.y], p[f.z])), glm::max(p[f.x], glm::max(p[f.y], p[f.z]))};
}

bool boxes_touch(const Box& a, const Box& b, double pad) {
  return glm::all(glm::lessThanEqual(a.lo - pad, b.hi)) && glm::all(glm::lessThanEqual(b.lo - pad, a.hi));
}

// Overlap of the projections of both triangles on the normal of edge (a, b), or +inf for a
// degenerate edge (which separates nothing).
double axis_overlap(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2 (&x)[3], const glm::dvec2 (&y)[3]) {
  glm::dvec2 axis(a.y - b.y, b.x - a.x);
  const double len = glm::length(axis);
  if (len == 0.0) return INFINITY;
  axis /= len;
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  for (int i = 0; i < 3; ++i) {
    const double px = glm::dot(axis, x[i]), py = glm::dot(axis, y[i]);
    x_lo = std::min(x_lo, px), x_hi = std::max(x_hi, px);
    y_lo = std::min(y_lo, py), y_hi = std::max(y_hi, py);
  }
  return std::min(x_hi, y_hi) - std::max(x_lo, y_lo);
}

bool coplanar_overlap(const std::vector<glm::dvec3>& p, const glm::uvec3& fx, const glm::uvec3& fy, double plane_tol,
                      double overlap_tol) {
  const glm::dvec3 n = glm::cross(p[fx.y] - p[fx.x], p[fx.z] - p[fx.x]);
  const double len = glm::length(n);
  if (len == 0.0) return false;
  const glm::dvec3 unit = n / len;
  for (int k = 0; k < 3; ++k)
    if (std::abs(glm::dot(unit, p[fy[k]] - p[fx.x])) > plane_tol) return false;
  const glm::dvec3 a = glm::abs(unit);
  const int drop = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const int u = drop == 0 ? 1 : 0, v = drop == 2 ? 1 : 2;
  glm::dvec2 x[3], y[3];
  for (int k = 0; k < 3; ++k) {
    x[k] = {p[fx[k]][u], p[fx[k]][v]};
    y[k] = {p[fy[k]][u], p[fy[k]][v]};
  }
  for (int k = 0; k < 3; ++k) {
    if (axis_overlap(x[k], x[(k + 1) % 3], x, y) <= overlap_tol) return false;
    if (axis_overlap(y[k], y[(k + 1) % 3], x, y) <= overlap_tol) return false;
  }
  return true;
}

bool shares_piece(const ConformFace& a, const ConformFace& b) {
  return a.piece == b.piece || a.piece == b.other || (a.other >= 0 && (a.other == b.piece || a.other == b.other));
}

}  // namespace

std::pair<std::int64_t, std::int64_t> find_nonconforming(const std::vector<glm::dvec3>& positions,
                                                        const std::vector<ConformFace>& faces, double plane_tolerance,
                                                        double overlap_tolerance) {
  std::vector<Box> boxes(faces.size());
  Box all{glm::dvec3(INFINITY), glm::dvec3(-INFINITY)};
  for (std::size_t i = 0; i < faces.size(); ++i) {
    boxes[i] = face_box(positions, faces[i].corners);
    all.lo = glm::min(all.lo, boxes[i].lo), all.hi = glm::max(all.hi, boxes[i].hi);
  }
  const glm::dvec3 extent = all.hi - all.lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  std::vector<std::uint32_t> order(faces.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return boxes[a].lo[axis] < boxes[b].lo[axis]; });
  std::vector<std::uint32_t> active;
  for (std::uint32_t i : order) {
    const double start = boxes[i].lo[axis] - plane_tolerance;
    active.erase(std::remove_if(active.begin(), active.end(), [&](std::uint32_t j) { return boxes[j].hi[axis] < start; }),
                 active.end());
    for (std::uint32_t j : active) {
      const bool i_hull = faces[i].other < 0, j_hull = faces[j].other < 0;
      if ((!i_hull && !j_hull) || shares_piece(faces[i], faces[j])) continue;
      if (!boxes_touch(boxes[i], boxes[j], plane_tolerance)) continue;
      // The hull face first; of two hull faces, the one of the lower piece (then face).
      const bool i_first = i_hull && (!j_hull || std::make_pair(faces[i].piece, faces[i].face) <
                                                     std::make_pair(faces[j].piece, faces[j].face));
      const std::uint32_t x = i_first ? i : j, y = i_first ? j : i;
      if (coplanar_overlap(positions, faces[x].corners, faces[y].corners, plane_tolerance, overlap_tolerance) ||
          coplanar_overlap(positions, faces[y].corners, faces[x].corners, plane_tolerance, overlap_tolerance))
        return {x, y};
    }
    active.push_back(i);
  }
  return {-1, -1};
}

}  // namespace fracref::coarse_detail
