#include "geom/intersect.hpp"

#include <algorithm>

#include "geom/predicates.hpp"

namespace fracref {
namespace {

using glm::dvec2;
using glm::dvec3;

dvec2 drop(const dvec3& p, int axis) {
  const int i = axis == 0 ? 1 : 0;
  const int j = axis == 2 ? 1 : 2;
  return {p[i], p[j]};
}

// An axis whose projection keeps the triangle non-degenerate, or -1 when the corners are
// collinear: the three projected orientations are the components of the normal.
int projection_axis(const dvec3& a, const dvec3& b, const dvec3& c) {
  for (int axis = 2; axis >= 0; --axis)
    if (orient2d_projected(a, b, c, axis) != 0) return axis;
  return -1;
}

int projection_axis(const Triangle3& t) { return projection_axis(t[0], t[1], t[2]); }

bool mixed_signs(int s1, int s2, int s3) {
  return (s1 > 0 || s2 > 0 || s3 > 0) && (s1 < 0 || s2 < 0 || s3 < 0);
}

// ---- 2D, on exact projections ----

bool in_box_2d(const dvec2& p, const dvec2& a, const dvec2& b) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

// Closed segments; the classic case analysis is exact for collinear and point segments.
bool segments_intersect_2d(const dvec2& a, const dvec2& b, const dvec2& c, const dvec2& d) {
  const int d1 = orient2d(c, d, a), d2 = orient2d(c, d, b);
  const int d3 = orient2d(a, b, c), d4 = orient2d(a, b, d);
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && in_box_2d(a, c, d)) || (d2 == 0 && in_box_2d(b, c, d)) || (d3 == 0 && in_box_2d(c, a, b)) ||
         (d4 == 0 && in_box_2d(d, a, b));
}

// \pre the triangle is not degenerate in this projection.
bool point_in_triangle_2d(const dvec2& p, const dvec2& a, const dvec2& b, const dvec2& c) {
  return !mixed_signs(orient2d(a, b, p), orient2d(b, c, p), orient2d(c, a, p));
}

// \pre the triangle is not degenerate in this projection.
bool segment_triangle_2d(const dvec2& a, const dvec2& b, const dvec2 t[3]) {
  if (point_in_triangle_2d(a, t[0], t[1], t[2])) return true;
  for (int k = 0; k < 3; ++k)
    if (segments_intersect_2d(a, b, t[k], t[(k + 1) % 3])) return true;
  return false;
}

// Coplanar non-degenerate triangles: either edges cross or one contains the other.
bool triangles_intersect_2d(const dvec2 p[3], const dvec2 q[3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (segments_intersect_2d(p[i], p[(i + 1) % 3], q[j], q[(j + 1) % 3])) return true;
  return point_in_triangle_2d(p[0], q[0], q[1], q[2]) || point_in_triangle_2d(q[0], p[0], p[1], p[2]);
}

// ---- 3D ----

// Segment against a non-degenerate triangle whose plane sides oa, ob of a and b are known.
bool segment_triangle_signs(const dvec3& a, const dvec3& b, int oa, int ob, const Triangle3& t, int axis) {
  if (oa * ob > 0) return false;
  if (oa == 0 && ob == 0) {
    const dvec2 t2[3] = {drop(t[0], axis), drop(t[1], axis), drop(t[2], axis)};
    return segment_triangle_2d(drop(a, axis), drop(b, axis), t2);
  }
  // The line ab pierces the plane inside the segment; it hits the closed triangle iff it passes
  // on the same side of all three edges.
  return !mixed_signs(orient3d(a, b, t[0], t[1]), orient3d(a, b, t[1], t[2]), orient3d(a, b, t[2], t[0]));
}

bool segment_triangle_nondegenerate(const dvec3& a, const dvec3& b, const Triangle3& t, int axis) {
  return segment_triangle_signs(a, b, orient3d(t[0], t[1], t[2], a), orient3d(t[0], t[1], t[2], b), t, axis);
}

// An axis on which not all of the points have the same coordinate, or -1.
int varying_axis(std::initializer_list<dvec3> pts) {
  for (int axis = 0; axis < 3; ++axis)
    for (const dvec3& p : pts)
      if (p[axis] != pts.begin()[0][axis]) return axis;
  return -1;
}

bool collinear(const dvec3& a, const dvec3& b, const dvec3& c) { return projection_axis(a, b, c) < 0; }

// Whether s lies on the closed segment [a,b], for collinear s, a, b.
bool between_collinear(const dvec3& s, const dvec3& a, const dvec3& b) {
  for (int k = 0; k < 3; ++k)
    if (s[k] < std::min(a[k], b[k]) || s[k] > std::max(a[k], b[k])) return false;
  return true;
}

// Whether the segments [s,a] and [s,b] share a point other than s: parallel, same direction.
bool same_ray(const dvec3& s, const dvec3& a, const dvec3& b) {
  if (a == s || b == s || !collinear(s, a, b)) return false;
  const int k = varying_axis({s, a});
  return (a[k] > s[k]) == (b[k] > s[k]) && b[k] != s[k];
}

// Whether the segment [s,x] meets triangle t = (s, y, z) (non-degenerate) beyond s: x lies in
// the plane of t and in the closed angular cone of t at s.
bool ray_enters(const dvec3& s, const dvec3& x, const dvec3& y, const dvec3& z) {
  if (x == s || orient3d(s, y, z, x) != 0) return false;
  const int axis = projection_axis(s, y, z);
  const dvec2 s2 = drop(s, axis), x2 = drop(x, axis), y2 = drop(y, axis), z2 = drop(z, axis);
  const int o = orient2d(s2, y2, z2);
  // x != s in 3D and the projection is injective on the plane, so x2 != s2: the two tests
  // below cannot both be zero, and together they reject the opposite rays.
  return orient2d(s2, y2, x2) * o >= 0 && orient2d(s2, x2, z2) * o >= 0;
}

// A segment-shaped piece of a face that touches the mesh's shared vertex s: either a segment
// starting at s ([s, end]) or a segment not containing s ([from, end]).
struct Piece {
  dvec3 from, end;
  bool from_s;
};

// The pieces covering a degenerate face (s, a, b) with collinear corners.
int degenerate_pieces(const dvec3& s, const dvec3& a, const dvec3& b, Piece out[3]) {
  int n = 0;
  out[n++] = {s, a, true};
  out[n++] = {s, b, true};
  if (!between_collinear(s, a, b)) out[n++] = {a, b, false};
  return n;
}

bool pieces_meet_beyond_s(const Piece& p, const Piece& q, const dvec3& s) {
  if (p.from_s && q.from_s) return same_ray(s, p.end, q.end);
  return segments_intersect(p.from, p.end, q.from, q.end);
}

// Degenerate face P = (s, a, b) against non-degenerate Q = (s, c, d).
bool degenerate_vs_face_beyond_s(const dvec3& s, const dvec3& a, const dvec3& b, const dvec3& c, const dvec3& d) {
  Piece pieces[3];
  const int n = degenerate_pieces(s, a, b, pieces);
  const Triangle3 q{s, c, d};
  const int axis = projection_axis(q);
  for (int k = 0; k < n; ++k) {
    const Piece& p = pieces[k];
    if (p.from_s ? ray_enters(s, p.end, c, d) : segment_triangle_nondegenerate(p.from, p.end, q, axis)) return true;
  }
  return false;
}

// Faces (s, a, b) and (s, c, d) sharing exactly the vertex s.
bool meet_beyond_shared_vertex(const dvec3& s, const dvec3& a, const dvec3& b, const dvec3& c, const dvec3& d) {
  // One face strictly on one side of the other's plane but for s: they meet only at s (the
  // common case of neighbours in a mesh, decided by two orientations; a degenerate face has no
  // plane, its orientations are 0 and the test falls through).
  auto one_side = [](int x, int y) { return x * y > 0; };
  if (one_side(orient3d(s, a, b, c), orient3d(s, a, b, d)) || one_side(orient3d(s, c, d, a), orient3d(s, c, d, b)))
    return false;
  const bool deg_p = collinear(s, a, b), deg_q = collinear(s, c, d);
  if (deg_p && deg_q) {
    Piece pp[3], pq[3];
    const int np = degenerate_pieces(s, a, b, pp), nq = degenerate_pieces(s, c, d, pq);
    for (int i = 0; i < np; ++i)
      for (int j = 0; j < nq; ++j)
        if (pieces_meet_beyond_s(pp[i], pq[j], s)) return true;
    return false;
  }
  if (deg_p) return degenerate_vs_face_beyond_s(s, a, b, c, d);
  if (deg_q) return degenerate_vs_face_beyond_s(s, c, d, a, b);
  // The intersection is convex and contains s; a second point lies on an edge of one face
  // inside the other. Edges opposite s cannot contain s; edges at s need the cone test.
  const Triangle3 p{s, a, b}, q{s, c, d};
  return segment_triangle_nondegenerate(a, b, q, projection_axis(q)) ||
         segment_triangle_nondegenerate(c, d, p, projection_axis(p)) || ray_enters(s, a, c, d) ||
         ray_enters(s, b, c, d) || ray_enters(s, c, a, b) || ray_enters(s, d, a, b);
}

// Faces (s, t, a) and (s, t, b) sharing exactly the edge st.
bool meet_beyond_shared_edge(const dvec3& s, const dvec3& t, const dvec3& a, const dvec3& b) {
  // Not coplanar: both faces have planes (a degenerate one makes the four points coplanar), and
  // two faces in different planes through st meet only along it.
  if (orient3d(s, t, a, b) != 0) return false;
  const bool deg_p = collinear(s, t, a), deg_q = collinear(s, t, b);
  if (!deg_p && !deg_q) {
    const int axis = projection_axis(s, t, a);
    return orient2d(drop(s, axis), drop(t, axis), drop(a, axis)) * orient2d(drop(s, axis), drop(t, axis), drop(b, axis)) > 0;
  }
  // A non-degenerate face meets the line st only along the edge itself.
  if (!deg_p || !deg_q) return false;
  if (s == t) return same_ray(s, a, b);
  const int k = varying_axis({s, t});
  const double lo = std::min(s[k], t[k]), hi = std::max(s[k], t[k]);
  return (a[k] < lo && b[k] < lo) || (a[k] > hi && b[k] > hi);
}

}  // namespace

bool segment_triangle_intersect(const dvec3& a, const dvec3& b, const Triangle3& t) {
  const int axis = projection_axis(t);
  if (axis >= 0) return segment_triangle_nondegenerate(a, b, t, axis);
  for (int k = 0; k < 3; ++k)
    if (segments_intersect(a, b, t[k], t[(k + 1) % 3])) return true;
  return false;
}

bool segments_intersect(const dvec3& a, const dvec3& b, const dvec3& c, const dvec3& d) {
  if (orient3d(a, b, c, d) != 0) return false;
  // Coplanar: a projection keeping any triple non-collinear is injective on their plane.
  for (int axis = 2; axis >= 0; --axis) {
    const dvec2 a2 = drop(a, axis), b2 = drop(b, axis), c2 = drop(c, axis), d2 = drop(d, axis);
    if (orient2d(a2, b2, c2) != 0 || orient2d(a2, b2, d2) != 0 || orient2d(a2, c2, d2) != 0 ||
        orient2d(b2, c2, d2) != 0)
      return segments_intersect_2d(a2, b2, c2, d2);
  }
  // Collinear: compare intervals along an axis on which the line is not constant.
  const int k = varying_axis({a, b, c, d});
  if (k < 0) return true;
  return std::max(std::min(a[k], b[k]), std::min(c[k], d[k])) <= std::min(std::max(a[k], b[k]), std::max(c[k], d[k]));
}

bool triangles_intersect(const Triangle3& p, const Triangle3& q) {
  // p strictly on one side of q's plane (q then has a plane): the common case, three orientations.
  int op[3], oq[3];
  for (int k = 0; k < 3; ++k) op[k] = orient3d(q[0], q[1], q[2], p[k]);
  if ((op[0] > 0 && op[1] > 0 && op[2] > 0) || (op[0] < 0 && op[1] < 0 && op[2] < 0)) return false;
  const int ap = projection_axis(p), aq = projection_axis(q);
  if (ap < 0 || aq < 0) {
    // A degenerate triangle is the union of its edges.
    const Triangle3& seg = ap < 0 ? p : q;
    const Triangle3& other = ap < 0 ? q : p;
    for (int k = 0; k < 3; ++k)
      if (segment_triangle_intersect(seg[k], seg[(k + 1) % 3], other)) return true;
    return false;
  }
  if (op[0] == 0 && op[1] == 0 && op[2] == 0) {
    const dvec2 p2[3] = {drop(p[0], aq), drop(p[1], aq), drop(p[2], aq)};
    const dvec2 q2[3] = {drop(q[0], aq), drop(q[1], aq), drop(q[2], aq)};
    return triangles_intersect_2d(p2, q2);
  }
  for (int k = 0; k < 3; ++k) oq[k] = orient3d(p[0], p[1], p[2], q[k]);
  if ((oq[0] > 0 && oq[1] > 0 && oq[2] > 0) || (oq[0] < 0 && oq[1] < 0 && oq[2] < 0)) return false;
  // Not coplanar: the intersection is a segment whose ends lie on edges of p or q.
  for (int k = 0; k < 3; ++k) {
    const int l = (k + 1) % 3;
    if (segment_triangle_signs(p[k], p[l], op[k], op[l], q, aq)) return true;
    if (segment_triangle_signs(q[k], q[l], oq[k], oq[l], p, ap)) return true;
  }
  return false;
}

bool mesh_faces_intersect(const std::vector<dvec3>& positions, const TriangleIds& ti, const TriangleIds& tj) {
  int shared = 0, first_i = -1, first_j = -1, second_i = -1, second_j = -1;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l)
      if (ti[k] == tj[l]) {
        ++shared;
        if (first_i < 0) {
          first_i = k;
          first_j = l;
        } else {
          second_i = k;
          second_j = l;
        }
      }
  auto at = [&](const TriangleIds& t, int k) -> const dvec3& { return positions[t[((k % 3) + 3) % 3]]; };
  if (shared == 0) return triangles_intersect({at(ti, 0), at(ti, 1), at(ti, 2)}, {at(tj, 0), at(tj, 1), at(tj, 2)});
  if (shared == 1)
    return meet_beyond_shared_vertex(at(ti, first_i), at(ti, first_i + 1), at(ti, first_i + 2), at(tj, first_j + 1),
                                     at(tj, first_j + 2));
  if (shared == 2) {
    const int rest_i = 3 - first_i - second_i, rest_j = 3 - first_j - second_j;
    return meet_beyond_shared_edge(at(ti, first_i), at(ti, second_i), at(ti, rest_i), at(tj, rest_j));
  }
  return true;
}

}  // namespace fracref
