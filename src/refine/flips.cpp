#include "refine/flips.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "geom/face_guard.hpp"
#include "geom/parallel.hpp"

#include "refine/topology_edit.hpp"

namespace fracref {

namespace {

struct Quad {
  glm::dvec3 a, b, c, d;  // faces (a, b, c), (b, a, d) -> (c, a, d), (d, b, c)
  double pa, pb, pc, pd;
};

double tri_energy(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double pa, double pb, double pc) {
  return 0.5 * glm::length(glm::cross(b - a, c - a)) * (pa + pb + pc) / 3.0;
}

glm::dvec3 unit_normal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  glm::dvec3 n = glm::cross(b - a, c - a);
  double l = glm::length(n);
  return l > 0.0 ? n / l : glm::dvec3(0.0);
}

// The cosine of the smallest angle of triangle (a, b, c) (1 for a degenerate one): angles compare
// as their cosines do, reversed, without an acos per corner.
double max_cosine(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  auto cosine = [](const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
    const glm::dvec3 u = q - p, v = r - p;
    const double lu = glm::length(u), lv = glm::length(v);
    if (lu == 0.0 || lv == 0.0) return 1.0;
    return std::clamp(glm::dot(u, v) / (lu * lv), -1.0, 1.0);
  };
  return std::max({cosine(a, b, c), cosine(b, c, a), cosine(c, a, b)});
}

bool flip_improves(const Quad& q, const FlipOptions& o) {
  const double cos_min = std::cos(o.min_angle * M_PI / 180.0);
  const double before = std::max(max_cosine(q.a, q.b, q.c), max_cosine(q.b, q.a, q.d));
  if (before <= cos_min) return false;
  const double after = std::max(max_cosine(q.c, q.a, q.d), max_cosine(q.d, q.b, q.c));
  if (after >= before) return false;
  glm::dvec3 n1 = unit_normal(q.a, q.b, q.c), n2 = unit_normal(q.b, q.a, q.d);
  if (glm::dot(n1, n2) < std::cos(o.max_dihedral * M_PI / 180.0)) return false;
  glm::dvec3 m1 = unit_normal(q.c, q.a, q.d), m2 = unit_normal(q.d, q.b, q.c);
  glm::dvec3 avg = n1 + n2;
  if (glm::dot(m1, avg) <= 0.0 || glm::dot(m2, avg) <= 0.0) return false;
  double e_old = tri_energy(q.a, q.b, q.c, q.pa, q.pb, q.pc) + tri_energy(q.b, q.a, q.d, q.pb, q.pa, q.pd);
  double e_new = tri_energy(q.c, q.a, q.d, q.pc, q.pa, q.pd) + tri_energy(q.d, q.b, q.c, q.pd, q.pb, q.pc);
  return e_new <= e_old;
}

// A flip changes which face of the quad lies on each of its four outer edges; at a junction
// (non-manifold) edge that turns the face around the edge to a new opposite vertex and can fold it
// past another piece's face, so quads touching a junction are left alone.
bool touches_junction(const FractureSurface& s, glm::uvec2 ab, glm::uvec2 cd) {
  for (std::uint32_t p : {ab.x, ab.y})
    for (std::uint32_t q : {cd.x, cd.y}) {
      std::uint32_t e = find_edge(s, p, q);
      if (e != kNoEdge && s.edge_special[e] == kEdgeNonManifold) return true;
    }
  return false;
}

// A flip that passes every test that does not depend on the pass's earlier flips.
struct FlipCandidate {
  std::uint32_t edge;
  glm::uvec2 opposite, faces;
};

// Candidates in edge order. Judged on S as the pass found it: a face flipped earlier in the pass
// is `used` and skipped later, and flip_edge leaves the other faces and the (stale) adjacency as
// they were, so each test below gives the answer it would give at its turn.
std::vector<FlipCandidate> candidate_flips(const FractureSurface& s, std::span<const glm::vec4> samples, const FlipOptions& o) {
  auto x = [&](std::uint32_t v) { return glm::dvec3(glm::vec3(s.positions[v])); };
  const double cos_min = std::cos(o.min_angle * M_PI / 180.0);
  // Only edges of a slim face are candidates: judged once per face, before the costlier tests.
  std::vector<char> slim(s.faces.size(), 0);
  geom_detail::parallel_chunks(s.faces.size(), geom_detail::chunk_count(s.faces.size(), 4096), o.threads,
                               [&](std::size_t, std::size_t begin, std::size_t end) {
                                 for (std::size_t f = begin; f < end; ++f)
                                   slim[f] = max_cosine(x(s.faces[f].x), x(s.faces[f].y), x(s.faces[f].z)) > cos_min;
                               });
  const std::size_t chunks = geom_detail::chunk_count(s.edges.size(), 4096);
  std::vector<std::vector<FlipCandidate>> parts(chunks);
  geom_detail::parallel_chunks(s.edges.size(), chunks, o.threads, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (auto e = std::uint32_t(begin); e < end; ++e) {
      glm::uvec2 cd, ff;
      if (s.edge_special[e] != kEdgeRegular) continue;
      const std::uint32_t f1 = s.ef_faces[s.ef_offsets[e]], f2 = s.ef_faces[s.ef_offsets[e] + 1];
      if (!(slim[f1] || slim[f2]) || !flip_candidates(s, e, cd, ff)) continue;
      const glm::uvec2 ab = s.edges[e];
      const Quad q{x(ab.x), x(ab.y), x(cd.x), x(cd.y), samples[ab.x].x, samples[ab.y].x, samples[cd.x].x, samples[cd.y].x};
      if (flip_improves(q, o) && !touches_junction(s, ab, cd)) parts[c].push_back({e, cd, ff});
    }
  });
  std::vector<FlipCandidate> out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

}  // namespace

std::size_t flip_slim_triangles(FractureSurface& s, std::span<const glm::vec4> samples, const ExteriorSurface&,
                                const FlipOptions& o) {
  const std::vector<FlipCandidate> candidates = candidate_flips(s, samples, o);
  if (candidates.empty()) return 0;
  // A flip moves surface inside its quad when the quad is not flat, which can cut through a
  // nearby sheet of S: every candidate's new faces are tested against S as the pass found it
  // (in parallel), then, in order, against the faces of the flips made before it.
  FaceGuard guard(double_positions(s), face_triangles(s));
  std::vector<std::vector<TriangleIds>> new_faces(candidates.size());
  std::vector<std::vector<std::uint32_t>> replaced(candidates.size());
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const FlipCandidate& c = candidates[k];
    const glm::uvec2 ab = s.edges[c.edge];
    new_faces[k] = {{c.opposite.x, ab.x, c.opposite.y}, {c.opposite.y, ab.y, c.opposite.x}};
    replaced[k] = {c.faces.x, c.faces.y};
  }
  const auto blockers = guard.snapshot_blockers(new_faces, replaced, o.threads);
  const auto conflicts = guard.batch_conflicts(new_faces, o.threads);
  std::vector<char> accepted(candidates.size(), 0);
  std::vector<char> used(s.faces.size(), 0);
  std::set<std::pair<std::uint32_t, std::uint32_t>> created;  // edges this pass made (adjacency is stale)
  std::size_t flips = 0;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const FlipCandidate& c = candidates[k];
    const std::uint32_t f1 = s.ef_faces[s.ef_offsets[c.edge]], f2 = s.ef_faces[s.ef_offsets[c.edge] + 1];
    const auto diagonal = std::minmax(c.opposite.x, c.opposite.y);
    if (used[f1] || used[f2] || created.count(diagonal)) continue;
    // A blocker still there (not replaced by a flip made so far: `used`) or a flip made so far
    // whose faces meet this one's refuses it.
    if (std::any_of(blockers[k].begin(), blockers[k].end(), [&](std::uint32_t g) { return used[g] == 0; })) continue;
    if (std::any_of(conflicts[k].begin(), conflicts[k].end(), [&](std::uint32_t j) { return accepted[j] != 0; })) continue;
    if (!flip_edge(s, c.edge)) continue;
    accepted[k] = 1;
    created.insert(diagonal);
    used[c.faces.x] = used[c.faces.y] = 1;
    ++flips;
  }
  if (flips) rebuild_after_flips(s);
  return flips;
}

}  // namespace fracref
