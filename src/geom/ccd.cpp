// The per-query narrow phase of ccd.hpp: inclusion-based bisection of the (t, u, v) box.
#include "geom/ccd.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

#include "geom/bvh.hpp"

// Error-free transformations and the error bounds below assume IEEE double arithmetic with
// round-to-nearest and no extended intermediate precision.
#if defined(__FAST_MATH__)
#error "fracref geom: exact predicates and CCD error bounds must not be built with -ffast-math"
#endif
static_assert(FLT_EVAL_METHOD == 0, "fracref geom: needs double evaluation without extended precision");

namespace fracref {
namespace {

using glm::dvec3;

constexpr double kU = 0x1p-53;  // unit roundoff

struct ParamBox {
  double t[2], u[2], v[2];
};

struct Direction {
  dvec3 n{0.0};
  dvec3 abs_n{0.0};
  double base = 0.0;  // sum |n_i| err_i + min_distance * |n|, rounded up
};

struct Query {
  bool vertex_triangle = true;
  dvec3 x0[4], x1[4];   // vertex-triangle: p, a, b, c; edge-edge: a, b, c, d
  dvec3 err{0.0};       // bound on the rounding error of one corner value, per coordinate
  dvec3 threshold{0.0}; // err + min_distance, rounded up
  Direction dirs[2];
  int num_dirs = 0;
  double tolerance = 0.0;
};

// F at the 8 corners of the box, index (it << 2) | (iu << 1) | iv. The evaluation order is the
// one the error bound in make_query was derived for: do not reorder.
void corner_values(const Query& q, const ParamBox& b, dvec3 f[8]) {
  for (int it = 0; it < 2; ++it) {
    const double t = b.t[it];
    dvec3 x[4];
    for (int k = 0; k < 4; ++k) x[k] = q.x0[k] + t * (q.x1[k] - q.x0[k]);
    for (int iu = 0; iu < 2; ++iu)
      for (int iv = 0; iv < 2; ++iv) {
        const double u = b.u[iu], v = b.v[iv];
        dvec3& out = f[(it << 2) | (iu << 1) | iv];
        if (q.vertex_triangle)
          out = x[0] - ((x[1] + u * (x[2] - x[1])) + v * (x[3] - x[1]));
        else
          out = (x[0] + u * (x[1] - x[0])) - (x[2] + v * (x[3] - x[2]));
      }
  }
}

// Whether n.F keeps one strict sign beyond min_distance*|n| over the box: for every corner,
// |fl(n.F~) - n.F| <= sum |n_i| err_i + gamma_3 sum |n_i| |F~_i| (gamma_3 < 4u), all rounded up.
bool separated_along(const Direction& d, const dvec3 f[8]) {
  bool positive = true, negative = true;
  for (int k = 0; k < 8 && (positive || negative); ++k) {
    const double g = glm::dot(d.n, f[k]);
    const double bound = (d.base + 4.0 * kU * glm::dot(d.abs_n, glm::abs(f[k]))) * (1.0 + 32.0 * kU);
    positive = positive && g > bound;
    negative = negative && g < -bound;
  }
  return positive || negative;
}

// Separation along a coordinate axis; sets the image bounds lo, hi of the box.
bool excluded_by_axes(const Query& q, const dvec3 f[8], dvec3& lo, dvec3& hi) {
  lo = hi = f[0];
  for (int k = 1; k < 8; ++k) {
    lo = glm::min(lo, f[k]);
    hi = glm::max(hi, f[k]);
  }
  for (int a = 0; a < 3; ++a)
    if (lo[a] > q.threshold[a] || hi[a] < -q.threshold[a]) return true;
  return false;
}

bool excluded_by_directions(const Query& q, const dvec3 f[8]) {
  for (int k = 0; k < q.num_dirs; ++k)
    if (separated_along(q.dirs[k], f)) return true;
  return false;
}

bool splittable(const double iv[2]) {
  const double mid = iv[0] + 0.5 * (iv[1] - iv[0]);
  return iv[0] < mid && mid < iv[1];
}

// The dimension whose extent changes F the most (a heuristic: any choice is correct), or -1
// when no dimension can be split any more.
int split_dimension(const ParamBox& b, const dvec3 f[8]) {
  double width[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < 8; ++k)
    for (int dim = 0; dim < 3; ++dim) {
      const int bit = 1 << (2 - dim);
      if (k & bit) continue;
      const dvec3 diff = glm::abs(f[k | bit] - f[k]);
      width[dim] = std::max(width[dim], std::max(diff.x, std::max(diff.y, diff.z)));
    }
  const bool can[3] = {splittable(b.t), splittable(b.u), splittable(b.v)};
  int best = -1;
  for (int dim = 0; dim < 3; ++dim)
    if (can[dim] && (best < 0 || width[dim] > width[best])) best = dim;
  return best;
}

void split(const ParamBox& b, int dim, ParamBox& first, ParamBox& second) {
  first = second = b;
  double* lo_half = dim == 0 ? first.t : (dim == 1 ? first.u : first.v);
  double* hi_half = dim == 0 ? second.t : (dim == 1 ? second.u : second.v);
  // Any split point inside the interval gives two halves covering it.
  const double mid = lo_half[0] + 0.5 * (lo_half[1] - lo_half[0]);
  lo_half[1] = mid;
  hi_half[0] = mid;
}

// Ericson, Real-Time Collision Detection 5.1.9: closest points of segments p1q1 and p2q2,
// returned as their difference (only a direction for the separation test; need not be exact).
dvec3 segment_segment_difference(const dvec3& p1, const dvec3& q1, const dvec3& p2, const dvec3& q2) {
  const dvec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
  double s = 0.0, t = 0.0;
  if (a > 0.0 && e > 0.0) {
    const double b = glm::dot(d1, d2), c = glm::dot(d1, r), denom = a * e - b * b;
    s = denom > 0.0 ? glm::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
    t = (b * s + f) / e;
    if (t < 0.0) {
      t = 0.0;
      s = glm::clamp(-c / a, 0.0, 1.0);
    } else if (t > 1.0) {
      t = 1.0;
      s = glm::clamp((b - c) / a, 0.0, 1.0);
    }
  } else if (e > 0.0) {
    t = glm::clamp(f / e, 0.0, 1.0);
  } else if (a > 0.0) {
    s = glm::clamp(-glm::dot(d1, r) / a, 0.0, 1.0);
  }
  return (p1 + s * d1) - (p2 + t * d2);
}

dvec3 closest_difference(const Query& q, const dvec3 x[4]) {
  if (q.vertex_triangle) return x[0] - closest_point_on_triangle(x[0], x[1], x[2], x[3]).point;
  return segment_segment_difference(x[0], x[1], x[2], x[3]);
}

void add_direction(Query& q, const dvec3& n, double min_distance) {
  if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z) || n == dvec3(0.0)) return;
  Direction& d = q.dirs[q.num_dirs++];
  d.n = n;
  d.abs_n = glm::abs(n);
  const double norm = std::sqrt(glm::dot(n, n)) * (1.0 + 8.0 * kU);
  d.base = (glm::dot(d.abs_n, q.err) + min_distance * norm) * (1.0 + 8.0 * kU);
}

Query make_query(bool vertex_triangle, const dvec3 x0[4], const dvec3 x1[4], const CcdOptions& options) {
  Query q;
  q.vertex_triangle = vertex_triangle;
  dvec3 m(0.0);
  for (int k = 0; k < 4; ++k) {
    q.x0[k] = x0[k];
    q.x1[k] = x1[k];
    m = glm::max(m, glm::max(glm::abs(x0[k]), glm::abs(x1[k])));
  }
  // corner_values performs at most 8 rounding steps on any path, and its absolute-value
  // evaluation is at most 18 M for parameters in [0, 1]: error <= gamma_8 * 18 M < 145 u M.
  // 162 u M leaves room for rounding in this line; 1e-300 covers underflow.
  q.err = 162.0 * kU * m + dvec3(1e-300);
  const double delta = std::max(0.0, options.min_distance);
  q.threshold = (q.err + dvec3(delta)) * (1.0 + 4.0 * kU);
  q.tolerance = options.tolerance;
  return q;
}

// The directions cost more than a box: computed only for queries the axes do not settle.
void add_directions(Query& q, double min_distance) {
  add_direction(q, closest_difference(q, q.x0), min_distance);
  add_direction(q, closest_difference(q, q.x1), min_distance);
}

bool solve(Query& q, const CcdOptions& options, CcdStats* stats) {
  thread_local std::vector<ParamBox> stack;
  stack.clear();
  stack.push_back({{0.0, 1.0}, {0.0, 1.0}, {0.0, 1.0}});
  int boxes = 0;
  bool collision = false, cap = false;
  while (!stack.empty()) {
    if (boxes >= options.max_iterations) {
      collision = cap = true;
      break;
    }
    ++boxes;
    const ParamBox b = stack.back();
    stack.pop_back();
    // Outside the triangle u + v <= 1 (fl is monotone, so fl(u+v) > 1 implies u+v > 1).
    if (q.vertex_triangle && b.u[0] + b.v[0] > 1.0) continue;
    dvec3 f[8], lo, hi;
    corner_values(q, b, f);
    if (excluded_by_axes(q, f, lo, hi)) continue;
    if (boxes == 1) add_directions(q, std::max(0.0, options.min_distance));
    if (excluded_by_directions(q, f)) continue;
    const dvec3 w = hi - lo;
    if (w.x <= q.tolerance && w.y <= q.tolerance && w.z <= q.tolerance) {
      collision = true;
      break;
    }
    const int dim = split_dimension(b, f);
    if (dim < 0) {
      collision = true;
      break;
    }
    ParamBox first, second;
    split(b, dim, first, second);
    stack.push_back(second);
    stack.push_back(first);
  }
  if (stats) stats->boxes = boxes, stats->hit_cap = cap, stats->solved = true;
  return collision;
}

}  // namespace

double segment_distance(const dvec3& p, const dvec3& q, const dvec3& r, const dvec3& s) {
  const dvec3 d1 = q - p, d2 = s - r, w = p - r;
  const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, w);
  double u = 0.0, v = 0.0;
  if (a <= 0.0 && e <= 0.0) return glm::length(w);
  if (a <= 0.0) {
    v = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = glm::dot(d1, w);
    if (e <= 0.0) {
      u = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = glm::dot(d1, d2), den = a * e - b * b;
      u = den > 0.0 ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
      v = (b * u + f) / e;
      if (v < 0.0) v = 0.0, u = std::clamp(-c / a, 0.0, 1.0);
      else if (v > 1.0) v = 1.0, u = std::clamp((b - c) / a, 0.0, 1.0);
    }
  }
  return glm::length((p + u * d1) - (r + v * d2));
}

namespace {

// A cheap conservative filter before the inclusion solver (segment_distance). Every point of a
// primitive moves on a convex combination of its corners' straight paths, so it travels at most
// its fastest corner's displacement; the distance between the two primitives therefore shrinks by
// at most the sum of both maxima. When the starting distance exceeds that sum (plus the solver's
// tolerance and a relative margin for the rounding of the distance itself), no contact is possible.

// The distance a pair must keep at the start to be cleared: both primitives' fastest corners
// plus the solver's margins (split: the first corner of the second primitive).
double needed_distance(const dvec3& p, const dvec3& q, const dvec3& r, const dvec3& s, const double travel[4],
                       int split, const CcdOptions& o) {
  const double first = split == 1 ? travel[0] : std::max(travel[0], travel[1]);
  const double second = std::max(split == 1 ? std::max(travel[1], travel[2]) : travel[2], travel[3]);
  const dvec3 m = glm::max(glm::max(glm::abs(p), glm::abs(q)), glm::max(glm::abs(r), glm::abs(s)));
  return (first + second) + o.min_distance + o.tolerance + 1e-12 * std::max(m.x, std::max(m.y, m.z));
}

bool far_apart(double distance, double needed) { return distance > needed + 1e-9 * distance; }

// The same test with lower bounds of the distance that need no division and no root: the gap
// between the two primitives' projections on a line n, compared as gap² > needed² |n|². Pairs the
// broad phase finds are mostly neighbours on the surface, nearly coplanar, and separated along one
// of: the line through their centroids (n scaled to integer weights), or a direction in their
// common plane perpendicular to one primitive's edge (a triangle's normal too). These cheap
// tests settle most pairs; the exact distance (a chain of divisions and a root) settles the
// rest. Their rounding (a few ulps of |n| scale) is far inside the 1e-12 scale margin, as with
// the exact distance.
template <int A, int B>
bool separated_along(const dvec3& n, const dvec3 (&a)[A], const dvec3 (&b)[B], double needed) {
  double alo = glm::dot(n, a[0]), ahi = alo, blo = glm::dot(n, b[0]), bhi = blo;
  for (int k = 1; k < A; ++k) {
    const double x = glm::dot(n, a[k]);
    alo = std::min(alo, x), ahi = std::max(ahi, x);
  }
  for (int k = 1; k < B; ++k) {
    const double x = glm::dot(n, b[k]);
    blo = std::min(blo, x), bhi = std::max(bhi, x);
  }
  const double gap = std::max(blo - ahi, alo - bhi), bound = needed * (1.0 + 1e-9);
  return gap > 0.0 && gap * gap > bound * bound * glm::dot(n, n);
}

bool edges_separated(const dvec3& p, const dvec3& q, const dvec3& r, const dvec3& s, double needed) {
  const dvec3 e[2] = {p, q}, f[2] = {r, s};
  if (separated_along((r + s) - (p + q), e, f, needed)) return true;
  const dvec3 d1 = q - p, d2 = s - r, m = glm::cross(d1, d2);
  return separated_along(glm::cross(d1, m), e, f, needed) || separated_along(glm::cross(d2, m), e, f, needed);
}

bool point_triangle_separated(const dvec3& p, const dvec3& a, const dvec3& b, const dvec3& c, double needed) {
  const dvec3 x[1] = {p}, t[3] = {a, b, c};
  if (separated_along(3.0 * p - (a + b + c), x, t, needed)) return true;
  const dvec3 normal = glm::cross(b - a, c - a);
  if (separated_along(normal, x, t, needed)) return true;
  for (const dvec3& n : {glm::cross(b - a, normal), glm::cross(c - b, normal), glm::cross(a - c, normal)})
    if (separated_along(n, x, t, needed)) return true;
  return false;
}

// The travels after taking the mean motion of the four corners out of every one: the distance
// between two primitives at time t, each point a convex combination of its corners, is the same
// when all corners move by c·t less (the weights sum to one on each side), so a pair whose
// relative travels cannot close its gap cannot collide. A relative margin covers the rounding.
// Whether they are smaller than the travels given, in sum (else the test would add nothing).
bool relative_travels(const dvec3* x0, const dvec3* x1, const double travel[4], double out[4]) {
  const dvec3 d[4] = {x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2], x1[3] - x0[3]};
  const dvec3 mean = 0.25 * ((d[0] + d[1]) + (d[2] + d[3]));
  double sum = 0.0, given = 0.0;
  for (int k = 0; k < 4; ++k) {
    out[k] = glm::length(d[k] - mean) * (1.0 + 1e-9) + 1e-300;
    sum += out[k], given += travel[k];
  }
  return sum < given;
}

void travels(const dvec3* x0, const dvec3* x1, double out[4]) {
  for (int i = 0; i < 4; ++i) out[i] = glm::length(x1[i] - x0[i]);
}

}  // namespace

bool ccd_vertex_triangle(const dvec3& p0, const dvec3& a0, const dvec3& b0, const dvec3& c0, const dvec3& p1,
                         const dvec3& a1, const dvec3& b1, const dvec3& c1, const double travel[4],
                         const CcdOptions& options, CcdStats* stats) {
  const dvec3 x0[4] = {p0, a0, b0, c0}, x1[4] = {p1, a1, b1, c1};
  auto apart = [&](const double* t) {
    const double needed = needed_distance(p0, a0, b0, c0, t, 1, options);
    return point_triangle_separated(p0, a0, b0, c0, needed) ||
           far_apart(std::sqrt(closest_point_on_triangle(p0, a0, b0, c0).squared_distance), needed);
  };
  if (stats) *stats = {};
  if (apart(travel)) return false;
  if (stats) stats->near = true;
  double relative[4];
  if (relative_travels(x0, x1, travel, relative) && apart(relative)) return false;
  Query q = make_query(true, x0, x1, options);
  return solve(q, options, stats);
}

bool ccd_edge_edge(const dvec3& a0, const dvec3& b0, const dvec3& c0, const dvec3& d0, const dvec3& a1,
                   const dvec3& b1, const dvec3& c1, const dvec3& d1, const double travel[4], const CcdOptions& options,
                   CcdStats* stats) {
  const dvec3 x0[4] = {a0, b0, c0, d0}, x1[4] = {a1, b1, c1, d1};
  auto apart = [&](const double* t) {
    const double needed = needed_distance(a0, b0, c0, d0, t, 2, options);
    return edges_separated(a0, b0, c0, d0, needed) || far_apart(segment_distance(a0, b0, c0, d0), needed);
  };
  if (stats) *stats = {};
  if (apart(travel)) return false;
  if (stats) stats->near = true;
  double relative[4];
  if (relative_travels(x0, x1, travel, relative) && apart(relative)) return false;
  Query q = make_query(false, x0, x1, options);
  return solve(q, options, stats);
}

bool ccd_vertex_triangle(const dvec3& p0, const dvec3& a0, const dvec3& b0, const dvec3& c0, const dvec3& p1,
                         const dvec3& a1, const dvec3& b1, const dvec3& c1, const CcdOptions& options,
                         CcdStats* stats) {
  const dvec3 x0[4] = {p0, a0, b0, c0}, x1[4] = {p1, a1, b1, c1};
  double travel[4];
  travels(x0, x1, travel);
  return ccd_vertex_triangle(p0, a0, b0, c0, p1, a1, b1, c1, travel, options, stats);
}

bool ccd_edge_edge(const dvec3& a0, const dvec3& b0, const dvec3& c0, const dvec3& d0, const dvec3& a1,
                   const dvec3& b1, const dvec3& c1, const dvec3& d1, const CcdOptions& options, CcdStats* stats) {
  const dvec3 x0[4] = {a0, b0, c0, d0}, x1[4] = {a1, b1, c1, d1};
  double travel[4];
  travels(x0, x1, travel);
  return ccd_edge_edge(a0, b0, c0, d0, a1, b1, c1, d1, travel, options, stats);
}

}  // namespace fracref
