// Traces that cross where the boundary of S doubles back on B (issue 6: a spike whose two sides
// run a hair apart, so that the straight trace of one side passes a vertex of the other on the
// wrong side), found exactly and re-routed clear of each other.
#include <gtest/gtest.h>

#include "geom/intersect.hpp"
#include "pieces/pieces_internal.hpp"
#include "pieces_test_support.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using namespace pieces_test;
using namespace pieces_detail;

// The boundary of S on the top of a box, K -> L -> R -> T (tip) -> P -> M: the spike's sides
// L-R-T and T-P run 0.04 apart at its base and converge on T, and R lies 1e-6 beyond the
// straight line T-P, so the trace of T-P crosses that of L-R next to R.
std::vector<EdgeTrace> spike_traces(const ExteriorMesh& m) {
  const std::vector<glm::dvec2> xy = {{0.5, 1.2}, {1.0, 1.48}, {1.5, 1.51 + 1e-6}, {2.0, 1.5}, {1.0, 1.52}, {0.5, 1.8}};
  std::vector<Location> at;
  for (const glm::dvec2& p : xy) at.push_back(locate_on_exterior(m, {p.x, p.y, 1.0}, 1e-6, nullptr));
  std::vector<EdgeTrace> traces;
  for (std::uint32_t i = 0; i + 1 < xy.size(); ++i)
    traces.push_back({i, 0, i, i + 1, trace_on_exterior(m, at[i], at[i + 1], 1e-9 * m.diagonal)});
  return traces;
}

TEST(PiecesUntangle, SpikeTracesAreReroutedClearOfEachOther) {
  const ExteriorMesh m = make_exterior_mesh(box({0, 0, -1}, {3, 3, 1}, 1));
  std::vector<EdgeTrace> traces = spike_traces(m);
  const std::vector<TraceConflict> before = find_trace_conflicts(m, traces);
  ASSERT_FALSE(before.empty());
  for (const TraceConflict& c : before) {  // only L-R (trace 1) and T-P (trace 3) cross
    EXPECT_EQ(std::min(c.trace_a, c.trace_b), 1u);
    EXPECT_EQ(std::max(c.trace_a, c.trace_b), 3u);
  }
  const std::vector<EdgeTrace> original = traces;
  const std::uint32_t added = untangle_traces(m, traces, 1e-9 * m.diagonal, 1e-6);
  EXPECT_GE(added, 1u);
  EXPECT_TRUE(find_trace_conflicts(m, traces).empty());
  std::size_t route_points = 0;
  for (std::size_t i = 0; i < traces.size(); ++i) {
    const Trace& t = traces[i].trace;
    EXPECT_TRUE(same_location(t.from, original[i].trace.from));
    EXPECT_TRUE(same_location(t.steps.back().to, original[i].trace.steps.back().to));
    EXPECT_EQ(t.steps.back().clear_of, kNone);
    for (const TraceStep& s : t.steps) {
      EXPECT_NEAR(s.to.point.z, 1.0, 1e-12);  // on the top of the box
      if (s.clear_of == kNone) continue;
      ++route_points;
      EXPECT_LT(s.clear_of, traces.size());
      EXPECT_NE(s.clear_of, i);
    }
  }
  EXPECT_GE(route_points, 1u);
}

// Without the spike's wrong-side vertex nothing crosses and nothing is re-routed.
TEST(PiecesUntangle, CleanTracesAreLeftAlone) {
  const ExteriorMesh m = make_exterior_mesh(box({0, 0, -1}, {3, 3, 1}, 1));
  std::vector<EdgeTrace> traces = spike_traces(m);
  traces[1].trace = trace_on_exterior(m, traces[1].trace.from, locate_on_exterior(m, {1.5, 1.5, 1.0}, 1e-6, nullptr), 1e-9 * m.diagonal);
  traces[2].trace = trace_on_exterior(m, traces[1].trace.steps.back().to, traces[2].trace.steps.back().to, 1e-9 * m.diagonal);
  EXPECT_TRUE(find_trace_conflicts(m, traces).empty());
  EXPECT_EQ(untangle_traces(m, traces, 1e-9 * m.diagonal, 1e-6), 0u);
}

// A cup hanging from the top of a sphere, its rim a circle with a spike: the rim goes out along
// L -> R -> T and back along the single edge T -> P. On the sphere, T -> P is a chord under B
// while R lies on B a little beyond the great circle through T and P: S does not intersect
// itself (the wings under the spike lean apart), but the trace of T -> P passes R on the wrong
// side and crosses the trace of L -> R.
struct Cup {
  std::vector<glm::vec4> positions;
  std::vector<glm::uvec4> faces;
};

Cup spike_cup(const Bvh& bvh, double wrong) {
  // Points of the tangent plane z = 1 mapped to the sphere (gnomonic: lines become great
  // circles), `depth` below it along the radius; rim points projected onto B in float.
  auto map = [&](glm::dvec2 p, double depth, bool rim) {
    glm::dvec3 x = (1.0 - depth) * glm::normalize(glm::dvec3(p, 1.0));
    if (rim) x = closest_point(bvh, x).point;
    return glm::vec4(glm::vec3(x), 1.0f);
  };
  auto polar = [](double r, double degrees) {
    const double a = degrees * 3.14159265358979 / 180.0;
    return glm::dvec2(r * std::cos(a), r * std::sin(a));
  };
  // Rim (counterclockwise from above) and its inner ring; the spike L R T P replaces angle 0.
  std::vector<glm::dvec2> rim, inner;
  const glm::dvec2 tip(0.6, 0.0), p_base = polar(0.3, 5.0), l_base = polar(0.3, -5.0);
  const glm::dvec2 r_mid(0.45, tip.y + (p_base.y - tip.y) * (0.6 - 0.45) / (0.6 - p_base.x) + wrong);
  for (int a = 20; a <= 340; a += 20) {
    rim.push_back(polar(0.3, a));
    inner.push_back(polar(0.15, a));
  }
  // Spike vertices after angle 340: L, R, T, P; inner points for L, R, P only (T is a tip).
  const std::uint32_t n = std::uint32_t(rim.size());
  rim.push_back(l_base);
  rim.push_back(r_mid);
  rim.push_back(tip);
  rim.push_back(p_base);
  inner.push_back({0.25, -0.06});   // under L: the out-wing leans to -y
  inner.push_back({0.40, -0.05});   // under R
  inner.push_back({0.25, 0.06});    // under P: the back wing leans to +y
  Cup cup;
  // Vertex ids: rim 0..n+3 (L = n, R = n+1, T = n+2, P = n+3), inner n+4.., centre last.
  for (const glm::dvec2& p : rim) cup.positions.push_back(map(p, 0.0, true));
  const std::uint32_t in0 = std::uint32_t(cup.positions.size());
  for (const glm::dvec2& p : inner) cup.positions.push_back(map(p, 0.1, false));
  const std::uint32_t centre = std::uint32_t(cup.positions.size());
  cup.positions.push_back(map({0.0, 0.0}, 0.25, false));
  // The rim loop with the inner vertex of each rim vertex (none for T).
  std::vector<std::uint32_t> loop, below;
  for (std::uint32_t i = 0; i < n; ++i) loop.push_back(i), below.push_back(in0 + i);
  loop.insert(loop.end(), {n, n + 1, n + 2, n + 3});
  below.insert(below.end(), {in0 + n, in0 + n + 1, kNone, in0 + n + 2});
  const std::size_t count = loop.size();
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t a = loop[i], b = loop[(i + 1) % count];
    const std::uint32_t ia = below[i], ib = below[(i + 1) % count];
    if (ia == kNone) {  // T -> P: the back wing
      cup.faces.emplace_back(a, b, ib, 0);
      cup.faces.emplace_back(a, ib, below[(i + count - 1) % count], 0);  // the fold (T, iP, iR)
    } else if (ib == kNone) {  // R -> T: the out-wing's last face
      cup.faces.emplace_back(a, b, ia, 0);
    } else {
      cup.faces.emplace_back(a, b, ib, 0);
      cup.faces.emplace_back(a, ib, ia, 0);
    }
  }
  std::vector<std::uint32_t> ring;
  for (std::uint32_t v : below)
    if (v != kNone) ring.push_back(v);
  for (std::size_t i = 0; i < ring.size(); ++i) cup.faces.emplace_back(ring[i], ring[(i + 1) % ring.size()], centre, 0);
  return cup;
}

TEST(PiecesUntangle, SpikeOnSphereBuildsValidPieces) {
  const MeshSoup b = icosphere(4);
  const Bvh bvh = build_bvh(b.positions, b.triangles);
  const Cup cup = spike_cup(bvh, 0.002);
  const FractureSurface s =
      make_fracture_surface(cup.positions, cup.faces, std::vector<glm::ivec2>(cup.faces.size(), glm::ivec2(1, 0)), 2);
  ASSERT_EQ(validate(s), "");
  std::vector<glm::dvec3> xyz;
  for (const glm::vec4& p : s.positions) xyz.emplace_back(glm::vec3(p));
  std::vector<TriangleIds> tris;
  for (const glm::uvec4& f : s.faces) tris.push_back({f.x, f.y, f.z});
  ASSERT_TRUE(find_self_intersections(xyz, tris, 1).empty()) << "the test surface must be valid";
  const PieceSet set = build_pieces(s, b);
  EXPECT_GE(set.traces_rerouted, 1u);
  expect_valid_pieces(set, b);
}

}  // namespace
}  // namespace fracref
