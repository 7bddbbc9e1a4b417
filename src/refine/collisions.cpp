#include "refine/collisions.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "geom/ccd.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {

// Threads for the per-vertex and per-face work below (projecting onto B, the inside test, faces
// near B, the rim faces' crossing test): each element is decided alone, so the result is the same
// for any count.

}  // namespace

void project_boundary_vertices(FractureSurface& s, const ExteriorSurface& b) {
  for (std::size_t i = 0; i < s.positions.size(); ++i)
    if (s.vertex_flags[i] & kVertexBoundary)
      s.positions[i] = glm::vec4(glm::vec3(b.closest_point(glm::dvec3(glm::vec3(s.positions[i])))), 1.0f);
}

void apply_boundary_constraint(const FractureSurface& s, const ExteriorSurface& b, const std::vector<glm::vec4>& x0,
                               std::vector<glm::vec4>& x1) {
  parallel_chunks(x1.size(), chunk_count(x1.size(), 4096), default_threads(), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if ((s.vertex_flags[i] & kVertexBoundary) && x1[i] != x0[i])
        x1[i] = glm::vec4(glm::vec3(b.closest_point(glm::dvec3(glm::vec3(x1[i])))), 1.0f);
  });
}

namespace {

// A query still undecided after this many boxes counts as a collision (conservative: its
// vertices are held). Such queries are pairs resting within a few tolerances of each other
// along a whole patch, where bisection needs ~(size/gap)² boxes: a few such queries would take
// most of the solver's time, and almost all of them end held anyway.
constexpr int kCcdBoxBudget = 4096;

// An interior vertex that ends closer to B than it travelled may have crossed it: only those
// need the (costlier) inside test. A cached lower bound of the distance to B, lowered by the
// travel of every step, spares most of the closest-point queries too.

bool keep_vertex_inside(const ExteriorSurface& b, const glm::vec4& x0, glm::vec4& x1, float& c) {
  const glm::dvec3 p0 = glm::dvec3(glm::vec3(x0)), p1 = glm::dvec3(glm::vec3(x1));
  double travel = glm::distance(p0, p1);
  if (c >= 0.0f && double(c) > 2.0 * travel) {
    c = float(c - travel);
    return false;
  }
  double d1 = std::sqrt(b.squared_distance(p1));
  if (d1 > travel || b.contains(p1)) {
    c = float(d1 * (1.0 - 1e-6));
    return false;
  }
  x1 = x0, c = -1.0f;
  return true;
}

// Without a clearance to keep, a vertex that stays put is not tested: it crosses nothing, and its
// distance would only have been kept.
std::size_t keep_inside(const FractureSurface& s, const ExteriorSurface& b, const std::vector<glm::vec4>& x0,
                        std::vector<glm::vec4>& x1, std::vector<float>* clearance) {
  std::vector<float> scratch;
  std::vector<float>& c = clearance ? *clearance : scratch;
  c.resize(x1.size(), -1.0f);
  const std::size_t chunks = chunk_count(x1.size(), 256);  // a query costs microseconds: small S splits too
  std::vector<std::size_t> reset(chunks, 0);
  parallel_chunks(
      x1.size(), chunks, default_threads(), [&](std::size_t k, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
          if (!(s.vertex_flags[i] & kVertexBoundary) && (clearance || x0[i] != x1[i]) &&
              keep_vertex_inside(b, x0[i], x1[i], c[i]))
            ++reset[k];
      });
  return std::accumulate(reset.begin(), reset.end(), std::size_t(0));
}

std::vector<glm::dvec3> to_double(const std::vector<glm::vec4>& x) {
  std::vector<glm::dvec3> out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = glm::dvec3(glm::vec3(x[i]));
  return out;
}

// The faces that may touch B during the step. Distance to B is 1-Lipschitz, and every point of a
// triangle lies within longest edge / √3 of one of its corners (the circumradius bounds it for an
// acute triangle, half the longest edge for another), so every point of a face stays at least
// (smallest corner clearance − longest edge / √3 − largest corner travel) away from B; faces with
// a positive bound cannot meet it and are left out of the (costly) test. The bound with the whole
// longest edge would keep more faces in it.
std::vector<std::array<std::uint32_t, 3>> faces_near_exterior(const std::vector<std::array<std::uint32_t, 3>>& tris,
                                                              const std::vector<glm::vec4>& x0,
                                                              const std::vector<glm::vec4>& x1,
                                                              const std::vector<float>& clearance) {
  if (clearance.size() != x0.size()) return tris;
  const std::size_t chunks = chunk_count(tris.size(), 4096);
  std::vector<std::vector<std::array<std::uint32_t, 3>>> parts(chunks);
  parallel_chunks(tris.size(), chunks, default_threads(), [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      const auto& t = tris[f];
      double lowest = 1e300, longest = 0.0, travel = 0.0;
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 a{glm::vec3(x0[t[k]])}, b{glm::vec3(x0[t[(k + 1) % 3]])};
        lowest = std::min(lowest, double(clearance[t[k]]) < 0.0 ? -1.0 : double(clearance[t[k]]));
        longest = std::max(longest, glm::distance(a, b));
        travel = std::max(travel, double(glm::distance(glm::vec3(x0[t[k]]), glm::vec3(x1[t[k]]))));
      }
      if (lowest - longest / std::sqrt(3.0) - travel <= 1e-6 * (longest + 1e-30) + 1e-12) parts[c].push_back(t);
    }
  });
  std::vector<std::array<std::uint32_t, 3>> near;
  for (const auto& part : parts) near.insert(near.end(), part.begin(), part.end());
  return near;
}

// A face with a corner on B (a rim face) touches B at that corner by construction, so S–B CCD
// ignores it and nothing would stop it from swinging out through a concave part of B. It is
// tested instead as a copy whose B corners are pulled kRimShrink of the way to its centroid:
// virtual vertices, appended after the real ones, each a fixed barycentric combination of the
// face's corners (so they move linearly with them). Only a strip of that width along the rim
// goes untested. A rim face none of whose corners moves takes part in no pair (S–B pairs need a
// moving element, and the rounds below only ever hold vertices back), so it is left out rather
// than tested for crossing B at every step.

struct RimFaces {
  std::vector<std::array<std::uint32_t, 3>> triangles;  // virtual ids for the B corners
  std::vector<std::uint32_t> owner;                     // per virtual vertex: its face in S
  std::vector<int> corner;                              // per virtual vertex: which corner it replaces
};

RimFaces rim_faces(const FractureSurface& s, const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1) {
  RimFaces rim;
  const auto base = static_cast<std::uint32_t>(s.positions.size());
  for (std::uint32_t f = 0; f < s.faces.size(); ++f) {
    const glm::uvec4 g = s.faces[f];
    // The flags first: most faces have no corner on B, and the flags are one word per vertex.
    if (!((s.vertex_flags[g.x] | s.vertex_flags[g.y] | s.vertex_flags[g.z]) & kVertexBoundary)) continue;
    if (x0[g.x] == x1[g.x] && x0[g.y] == x1[g.y] && x0[g.z] == x1[g.z]) continue;
    std::array<std::uint32_t, 3> t = {g.x, g.y, g.z};
    bool any = false;
    for (int k = 0; k < 3; ++k) {
      if (!(s.vertex_flags[t[k]] & kVertexBoundary)) continue;
      any = true;
      t[k] = base + std::uint32_t(rim.owner.size());
      rim.owner.push_back(f);
      rim.corner.push_back(k);
    }
    if (any) rim.triangles.push_back(t);
  }
  return rim;
}

// Rim faces that already cross B or lie outside it at x0 (the coarse surface can bulge out of B
// near its rim) are left out: holding them back would only keep them outside, while the flow may
// pull them in. Crossing is tested exactly (a B edge piercing the face is no vertex–triangle or
// edge–edge contact, so CCD over a zero step would not see it). A face that does not meet B lies
// wholly on one side of it, so a real corner with a positive clearance (inside B, off it) settles
// the side without the costly inside test (three quarters of this function's time otherwise).
void drop_crossing_rim_faces(RimFaces& rim, const std::vector<glm::dvec3>& p0_rim, const ExteriorSurface& b,
                             const std::vector<float>& clearance) {
  const auto inside_corner = [&](const std::array<std::uint32_t, 3>& tri) {
    for (std::uint32_t v : tri)
      if (v < clearance.size() && clearance[v] > 0.0f) return true;  // virtual ids are past the real ones
    return false;
  };
  std::vector<char> keep(rim.triangles.size(), 0);
  parallel_chunks(keep.size(), chunk_count(keep.size(), 128), default_threads(),
                  [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t k = begin; k < end; ++k) {
                      const auto& tri = rim.triangles[k];
                      const glm::dvec3 &x = p0_rim[tri[0]], &y = p0_rim[tri[1]], &z = p0_rim[tri[2]];
                      keep[k] = !b.meets(x, y, z) && (inside_corner(tri) || b.contains((x + y + z) / 3.0));
                    }
                  });
  std::size_t kept = 0;
  for (std::size_t k = 0; k < keep.size(); ++k)
    if (keep[k]) rim.triangles[kept++] = rim.triangles[k];
  rim.triangles.resize(kept);
}

std::vector<glm::dvec3> with_rim_points(const FractureSurface& s, const RimFaces& rim, std::vector<glm::dvec3> x) {
  for (std::size_t k = 0; k < rim.owner.size(); ++k) {
    const glm::uvec4 f = s.faces[rim.owner[k]];
    const glm::dvec3 centroid = (x[f.x] + x[f.y] + x[f.z]) / 3.0;
    const glm::dvec3 c = x[f[rim.corner[k]]];
    x.push_back(c + kRimShrink * (centroid - c));
  }
  return x;
}

}  // namespace

// What the first search of a step keeps for the later ones (StepCollisions).
struct StepCollisions::State {
  const FractureSurface& s;
  const ExteriorSurface& b;
  const std::vector<glm::vec4>& x0;
  std::vector<std::array<std::uint32_t, 3>> tris, near_b;
  std::vector<std::array<std::uint32_t, 2>> edges;
  RimFaces rim;
  std::vector<std::uint8_t> on_b;
  std::vector<glm::dvec3> p0, p0_rim;
  std::vector<CcdPair> examined;   // the first search's candidate pairs within S
  std::vector<glm::vec4> last;     // x1 as the last call left it (empty: no search yet)

  State(const FractureSurface& s, const ExteriorSurface& b, const std::vector<glm::vec4>& x0) : s(s), b(b), x0(x0) {
    tris.resize(s.faces.size());
    for (std::size_t f = 0; f < s.faces.size(); ++f) tris[f] = {s.faces[f].x, s.faces[f].y, s.faces[f].z};
    edges.resize(s.edges.size());
    for (std::size_t e = 0; e < s.edges.size(); ++e)
      edges[e] = {std::min(s.edges[e].x, s.edges[e].y), std::max(s.edges[e].x, s.edges[e].y)};
    p0 = to_double(x0);
  }

  // The faces that may meet B and the rim faces, for the motion x0 → x1 of the first search: a
  // later motion only holds vertices back, so they cover it too.
  void prepare(const std::vector<glm::vec4>& x1, const std::vector<float>& clearance_at_x0) {
    near_b = faces_near_exterior(tris, x0, x1, clearance_at_x0);
    rim = rim_faces(s, x0, x1);
    on_b.assign(x1.size() + rim.owner.size(), 0);
    for (std::size_t i = 0; i < x1.size(); ++i) on_b[i] = (s.vertex_flags[i] & kVertexBoundary) ? 1 : 0;
    p0_rim = with_rim_points(s, rim, p0);
    drop_crossing_rim_faces(rim, p0_rim, b, clearance_at_x0);
    near_b.insert(near_b.end(), rim.triangles.begin(), rim.triangles.end());
    examined.clear();
  }

  // Flags the vertices whose end position changed since the last call; false when one moved
  // anywhere but back to x0 (the pairs kept then do not cover the motion: search again).
  bool changed_since_last(const std::vector<glm::vec4>& x1, std::vector<std::uint8_t>& changed) const {
    if (last.size() != x1.size()) return false;
    for (std::size_t i = 0; i < x1.size(); ++i) {
      if (x1[i] == last[i]) continue;
      if (x1[i] != x0[i]) return false;
      changed[i] = 1;
    }
    return true;
  }

  std::size_t rounds(std::vector<glm::vec4>& x1, std::vector<std::uint8_t>& reset_now, bool searched);
};

// Each round resets every vertex of every colliding pair; the moving set shrinks strictly, so
// the loop ends. After a search only pairs with a vertex reset since can have changed, and only
// among the pairs the search examined (holding vertices back only shrinks the motion): later
// rounds, and later calls on the same step, test those instead of searching S again.
std::size_t StepCollisions::State::rounds(std::vector<glm::vec4>& x1, std::vector<std::uint8_t>& reset_now,
                                          bool searched) {
  StepCcdOptions opts;
  opts.ccd.tolerance = 1e-7 * b.diagonal();
  opts.ccd.max_iterations = kCcdBoxBudget;
  opts.skip_resting_pairs = true;  // resting pairs cannot change by freezing (see the loop's end)
  std::size_t stopped = 0;
  std::vector<glm::dvec3> p1 = to_double(x1);  // kept equal to x1: a held vertex goes back to p0
  for (int round = 0;; ++round) {
    const bool incremental = searched || round > 0;
    opts.active_vertices = incremental ? &reset_now : nullptr;
    opts.edges = &edges;
    opts.examined = incremental ? nullptr : &examined;
    opts.candidates = incremental ? &examined : nullptr;
    std::vector<CcdPair> pairs = find_step_collisions(p0, p1, tris, opts);
    opts.edges = nullptr;
    opts.examined = nullptr;
    opts.candidates = nullptr;
    // Against B, a virtual rim vertex is active when a corner of its face is.
    std::vector<std::uint8_t> reset_rim;
    if (incremental) {
      reset_rim = reset_now;
      for (std::size_t k = 0; k < rim.owner.size(); ++k) {
        const glm::uvec4 f = s.faces[rim.owner[k]];
        reset_rim.push_back(reset_now[f.x] | reset_now[f.y] | reset_now[f.z]);
      }
      opts.active_vertices = &reset_rim;
    }
    opts.ignored_vertices = &on_b;
    std::vector<CcdPair> with_b =
        find_step_collisions_with_static(p0_rim, with_rim_points(s, rim, p1), near_b, b.ccd, opts);
    opts.ignored_vertices = nullptr;
    if (pairs.empty() && with_b.empty()) break;
    const std::size_t before = stopped;
    std::fill(reset_now.begin(), reset_now.end(), 0);
    auto freeze = [&](std::uint32_t v) {
      auto hold = [&](std::uint32_t c) {
        if (x1[c] != x0[c]) x1[c] = x0[c], p1[c] = p0[c], reset_now[c] = 1, ++stopped;
      };
      if (v < x1.size()) return hold(v);
      const glm::uvec4 f = s.faces[rim.owner[v - x1.size()]];  // a rim face's virtual vertex: hold the face
      hold(f.x), hold(f.y), hold(f.z);
    };
    for (const CcdPair& p : pairs)
      for (std::uint32_t v : p.vertices) freeze(v);
    for (const CcdPair& p : with_b) {
      if (p.kind == CcdKind::vertex_triangle) freeze(p.vertices[0]);
      else if (p.kind == CcdKind::triangle_vertex) freeze(p.vertices[1]), freeze(p.vertices[2]), freeze(p.vertices[3]);
      else freeze(p.vertices[0]), freeze(p.vertices[1]);
    }
    // A pair whose vertices all stay put was within the CCD tolerance before the step already
    // (conservative CCD reports such contacts): holding vertices back cannot change it.
    if (stopped == before) break;
  }
  return stopped;
}


StepCollisions::StepCollisions(const FractureSurface& s, const ExteriorSurface& exterior,
                               const std::vector<glm::vec4>& x0)
    : state_(std::make_unique<State>(s, exterior, x0)) {}

StepCollisions::~StepCollisions() = default;

std::size_t StepCollisions::apply(std::vector<glm::vec4>& x1, std::vector<float>* clearance) {
  State& z = *state_;
  const std::vector<float> clearance_at_x0 = clearance ? *clearance : std::vector<float>();
  std::size_t stopped = keep_inside(z.s, z.b, z.x0, x1, clearance);
  std::vector<std::uint8_t> reset_now(x1.size(), 0);
  const bool searched = z.changed_since_last(x1, reset_now);
  if (!searched) z.prepare(x1, clearance_at_x0);
  stopped += z.rounds(x1, reset_now, searched);
  z.last = x1;
  return stopped;
}

std::size_t apply_collision_constraints(const FractureSurface& s, const ExteriorSurface& b,
                                        const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1,
                                        std::vector<float>* clearance) {
  return StepCollisions(s, b, x0).apply(x1, clearance);
}

}  // namespace fracref
