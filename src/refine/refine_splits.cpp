// The refiner's samples and splits (paper 4.4): one sample per element, judged by how far the
// flow would take it off its element, split by longest-edge bisection where it would go farther
// than tau.
#include <algorithm>
#include <cmath>
#include <limits>

#include "flow/implicit_step.hpp"
#include "refine/collisions.hpp"
#include "refine/junction_order.hpp"
#include "refine/refiner.hpp"
#include "util/parallel.hpp"

namespace fracref::refine_detail {
namespace {

// Same arithmetic as surface_energy (double from the float positions) so that an accepted split
// cannot raise the energy the report measures by more than rounding.
double face_energy(const glm::vec3& fa, const glm::vec3& fb, const glm::vec3& fc, double pa, double pb, double pc) {
  glm::dvec3 a(fa), b(fb), c(fc);
  double area = 0.5 * glm::length(glm::cross(b - a, c - a));
  return area * (pa + pb + pc) / 3.0;
}

// The energy change of a split with the new vertex at `p` with field value psi_p:
// Σ_new A ψ̄ − Σ_old A ψ̄ over the faces it replaces.
double split_delta_energy(const FractureSurface& s, const std::vector<glm::vec4>& psi, const SplitRequest& r,
                          const glm::vec3& p, float psi_p) {
  auto x = [&](std::uint32_t v) { return glm::vec3(s.positions[v]); };
  auto q = [&](std::uint32_t v) { return double(psi[v].x); };
  if (r.kind == SplitRequest::kFace) {
    glm::uvec4 f = s.faces[r.element];
    return face_energy(x(f.x), x(f.y), p, q(f.x), q(f.y), psi_p) + face_energy(x(f.y), x(f.z), p, q(f.y), q(f.z), psi_p) +
           face_energy(x(f.z), x(f.x), p, q(f.z), q(f.x), psi_p) - face_energy(x(f.x), x(f.y), x(f.z), q(f.x), q(f.y), q(f.z));
  }
  glm::uvec2 e = s.edges[r.element];
  double delta = 0.0;
  for (std::uint32_t k = s.ef_offsets[r.element]; k < s.ef_offsets[r.element + 1]; ++k) {
    glm::uvec4 f = s.faces[s.ef_faces[k]];
    std::uint32_t z = f.x + f.y + f.z - e.x - e.y;  // the vertex opposite the edge
    delta += face_energy(x(e.x), p, x(z), q(e.x), psi_p, q(z)) + face_energy(p, x(e.y), x(z), psi_p, q(e.y), q(z)) -
             face_energy(x(e.x), x(e.y), x(z), q(e.x), q(e.y), q(z));
  }
  return delta;
}

// A sampled element's shortest edge, and the direction its offsets are measured against: a
// face's unit normal (the offset is the motion across the face), an edge's unit axis (the motion
// across the edge); zero for a degenerate element (no offset).
struct ElementShape {
  bool face = false;
  glm::vec3 dir{0.0f};
  float shortest = 0.0f;
};

ElementShape element_shape(const FractureSurface& s, const SplitRequest& r) {
  auto x = [&](std::uint32_t v) { return glm::vec3(s.positions[v]); };
  ElementShape out;
  if (r.kind == SplitRequest::kFace) {
    const glm::uvec4 f = s.faces[r.element];
    const glm::vec3 n = glm::cross(x(f.y) - x(f.x), x(f.z) - x(f.x));
    const float nl = glm::length(n);
    out.face = true;
    if (nl > 0.0f) out.dir = n / nl;
    out.shortest = std::min({glm::distance(x(f.x), x(f.y)), glm::distance(x(f.y), x(f.z)), glm::distance(x(f.z), x(f.x))});
    return out;
  }
  const glm::uvec2 e = s.edges[r.element];
  const glm::vec3 axis = x(e.y) - x(e.x);
  const float len = glm::length(axis);
  out.shortest = len;
  if (len > 0.0f) out.dir = axis / len;
  return out;
}

// How far a motion d takes a point off the element (see ElementShape).
float element_offset(const ElementShape& e, const glm::vec3& d) {
  if (e.dir == glm::vec3(0.0f)) return 0.0f;
  return e.face ? std::abs(glm::dot(d, e.dir)) : glm::length(d - glm::dot(d, e.dir) * e.dir);
}

}  // namespace

// The edge a split asked for at `r` bisects: the longest edge of the sampled face, or of the
// faces around the sampled edge when one of them is longer than it (else the edge itself), split
// at its midpoint (`start`). The paper splits a face 1-to-3 at the sample and a special edge at
// the sample; each such split keeps the element's long edges, so repeated splits, above all of
// the junction edges sampled every iteration, left fans of needles whose normals no flip could
// mend, which the fold guard and the collisions then held still. Longest-edge bisection (Rivara
// 1984) keeps every angle above a bound set by the coarse surface: the sample still says where
// S needs triangles, the bisection only how they are cut.
SplitRequest Refiner::bisection(const SplitRequest& r, bool propagate, glm::vec3& start, bool& path_left) const {
  auto length = [&](std::uint32_t e) {
    return glm::distance(glm::vec3(s_.positions[s_.edges[e].x]), glm::vec3(s_.positions[s_.edges[e].y]));
  };
  std::uint32_t edge = r.element;
  float longest = r.kind == SplitRequest::kEdge ? length(edge) : -1.0f;
  auto consider_face = [&](std::uint32_t f) {
    for (int c = 0; c < 3; ++c)
      if (const float l = length(s_.face_edges[3 * f + c]); l > longest) longest = l, edge = s_.face_edges[3 * f + c];
  };
  auto consider_faces_around = [&](std::uint32_t e) {
    for (std::uint32_t k = s_.ef_offsets[e]; k < s_.ef_offsets[e + 1]; ++k) consider_face(s_.ef_faces[k]);
  };
  auto midpoint = [&](std::uint32_t e) {
    const glm::uvec2 ab = s_.edges[e];
    const glm::vec3 m = 0.5f * (glm::vec3(s_.positions[ab.x]) + glm::vec3(s_.positions[ab.y]));
    return s_.edge_special[e] == kEdgeBoundary ? glm::vec3(b_.closest_point(glm::dvec3(m))) : m;
  };
  if (r.kind == SplitRequest::kFace) consider_face(r.element);
  else consider_faces_around(r.element);
  // The longest-edge propagating path (Rivara 1997): while a face across the chosen regular edge
  // has a longer edge, that edge goes first. Splitting an edge that is not its neighbour's longest
  // cut the neighbour into a needle, and a large face beside a refined patch became a fan of them.
  // Each step takes a strictly longer edge, so the path ends.
  const std::uint32_t own = edge;
  for (std::uint32_t from = kNoEdge; propagate && from != edge && s_.edge_special[edge] == kEdgeRegular;) {
    from = edge;
    consider_faces_around(edge);
  }
  path_left = edge != own;
  start = midpoint(edge);
  return {SplitRequest::kEdge, edge, glm::vec3(0.5f, 0.5f, 0.0f)};
}

// A sample whose flow step would take it too far from its element (paper 4.4: "if it moves too
// far away from the triangle after one iteration, we add it as a new vertex") asks for a split
// there, when moving it where the step would take it lowers the energy; the split is the
// longest-edge bisection of its element (Refiner::bisection), made unless it would reorder the
// sheets around a junction edge or make S cross itself (drop_crossing_splits). The tree records
// the new vertex's weights on the split edge (its position at creation). A split on S leaves the
// shape as it was up to that rounding, so no collision test is needed here: the flow step that
// follows moves the new vertices with all the others, under the same collision constraints. (A
// rim edge lies in one triangle of B, so its midpoint is on B.) `graded` counts the splits whose
// longest-edge path led away from their sample's element.
std::size_t Refiner::refine_step(std::uint32_t iteration, bool propagate, std::size_t& graded) {
  const float scale = float(o_.scale);
  SampleSet set = draw_samples(s_, o_.seed, iteration, float(o_.delta) * scale, float(o_.rim_delta) * scale);
  std::vector<char> on_boundary(set.points.size(), 0);
  parallel_chunks(set.points.size(), chunk_count(set.points.size(), 4096), default_threads(),
                  [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t k = begin; k < end; ++k) {
                      const SplitRequest& r = set.requests[k];
                      if (r.kind != SplitRequest::kEdge || s_.edge_special[r.element] != kEdgeBoundary) continue;
                      set.points[k] = glm::vec4(glm::vec3(b_.closest_point(glm::dvec3(set.points[k]))), 1.0f);
                      on_boundary[k] = 1;
                    }
                  });
  std::vector<glm::vec4> out(set.points.size());
  be_.sample_tests(s_.positions, samples_, SampleView{set.points, set.fan_offsets, set.fan_pairs}, out);
  // Verdicts side by side, then the splits in sample order: at most one per face, within budget.
  std::vector<Verdict> verdicts(set.points.size());
  const float tau = float(o_.tau) * scale;
  parallel_chunks(set.points.size(), chunk_count(set.points.size(), 1024), default_threads(),
                  [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t k = begin; k < end; ++k) verdicts[k] = judge_sample(set, k, out[k], on_boundary[k], tau);
                  });
  SplitChoice choice;
  choice.touched.assign(s_.faces.size(), 0);
  choice.faces = s_.faces.size();
  for (std::size_t k = 0; k < set.points.size() && !budget_reached_; ++k) {
    if (!verdicts[k].split) continue;
    glm::vec3 start;
    bool path_left = false;
    const SplitRequest r = bisection(set.requests[k], propagate, start, path_left);
    if (!split_keeps_junction_order(s_, r, start) || !choice.add(s_, r, o_.max_triangles, budget_reached_)) continue;
    choice.start.push_back(start);
    choice.graded.push_back(path_left);
  }
  drop_crossing_splits(choice);
  graded = std::size_t(std::count(choice.graded.begin(), choice.graded.end(), char(1)));
  apply_splits(s_, tree_, choice.chosen, &choice.start);
  inherit_clearance(s_, tree_, clearance_);
  inherit_moves();
  return choice.chosen.size();
}

// Splits keep S's shape only up to the rounding of their new vertices: where two sheets touch
// (where the coarse surface's sheets meet at a junction on B, the clay's with seed 6 within 3e-8)
// that rounding alone made them cross. Such splits are not made.
void Refiner::drop_crossing_splits(SplitChoice& choice) const {
  const std::vector<char> crossing = splits_that_cross(s_, choice.chosen, choice.start);
  std::size_t kept = 0;
  for (std::size_t k = 0; k < crossing.size(); ++k)
    if (!crossing[k])
      choice.chosen[kept] = choice.chosen[k], choice.start[kept] = choice.start[k], choice.graded[kept++] = choice.graded[k];
  choice.chosen.resize(kept), choice.start.resize(kept), choice.graded.resize(kept);
}

bool Refiner::SplitChoice::add(const FractureSurface& s, const SplitRequest& r, std::size_t max_faces, bool& over_budget) {
  // The faces the split replaces: the face, or the faces around the edge.
  const std::uint32_t* first = r.kind == SplitRequest::kFace ? &r.element : s.ef_faces.data() + s.ef_offsets[r.element];
  const std::uint32_t* last = r.kind == SplitRequest::kFace ? first + 1 : s.ef_faces.data() + s.ef_offsets[r.element + 1];
  if (std::any_of(first, last, [&](std::uint32_t f) { return touched[f] != 0; })) return false;
  const std::size_t added = r.kind == SplitRequest::kFace ? 2 : std::size_t(last - first);
  if (faces + added > max_faces) {
    over_budget = true;
    return false;
  }
  faces += added;
  std::for_each(first, last, [&](std::uint32_t f) { touched[f] = 1; });
  chosen.push_back(r);
  return true;
}

// A new vertex's last motion is its parents' interpolated: the motion of the point of S it was.
void Refiner::inherit_moves() {
  const std::size_t first = last_move_.size();
  last_move_.resize(s_.positions.size(), glm::vec3(0.0f));
  for (std::size_t v = first; v < last_move_.size(); ++v)
    for (int k = 0; k < 3; ++k)
      if (tree_.weights[v][k] != 0.0f) last_move_[v] += tree_.weights[v][k] * last_move_[tree_.parents[v][k]];
}

// A sample is judged by the same semi-implicit step as a vertex (flow/implicit_step.hpp), solved
// for the sample alone with its element's corners moving as they did in the last step:
//     (M_s + dt W_s) d_s = dt M_s v_s + dt Σ_k w_k d_k,
// M_s the mass of the sample's fan, v_s its velocity (K3), w_k the cotangent weights of
// its spokes, W_s their sum, d_k the corners' last motion. A large element lets the sample go
// nearly as far as the explicit step dt·v_s; a small one ties it to its corners, so the offset
// shrinks with the element and refinement ends where ψ is resolved at τ.
glm::vec3 Refiner::sample_step(const SampleSet& set, std::size_t k, const glm::vec4& tested) const {
  const glm::dvec3 p(glm::vec3(set.points[k]));
  double mass = 0.0, weight_sum = 0.0;
  glm::dvec3 pull(0.0);
  // Spoke weights per fan corner (a vertex of S), summed as in the matrix.
  std::uint32_t ids[16];
  double w[16];
  int count = 0;
  auto add = [&](std::uint32_t v, double x) {
    for (int c = 0; c < count; ++c)
      if (ids[c] == v) return void(w[c] += x);
    if (count < 16) ids[count] = v, w[count++] = x;
  };
  for (std::uint32_t t = set.fan_offsets[k]; t < set.fan_offsets[k + 1]; ++t) {
    const glm::uvec2 ab = set.fan_pairs[t];
    const glm::dvec3 a(glm::vec3(s_.positions[ab.x])), b(glm::vec3(s_.positions[ab.y]));
    const double psi = (double(tested.w) + samples_[ab.x].x + samples_[ab.y].x) / 3.0;
    const glm::dvec2 cot = corner_cotangents(p, a, b);
    add(ab.x, 0.5 * psi * cot.y);
    add(ab.y, 0.5 * psi * cot.x);
    mass += glm::length(glm::cross(a - p, b - p)) / 6.0;
  }
  for (int c = 0; c < count; ++c) {
    weight_sum += w[c];
    if (ids[c] < last_move_.size()) pull += w[c] * glm::dvec3(last_move_[ids[c]]);
  }
  const double denom = mass + dt_ * weight_sum;
  if (!(denom > 0.0)) return glm::vec3(0.0f);
  return glm::vec3((dt_ * mass * glm::dvec3(glm::vec3(tested)) + dt_ * pull) / denom);
}

// The sample's offset is its step relative to the motion its element's corners interpolate to
// at the sample (their last step's), across the element: zero where the element moves as a
// whole.
Refiner::Verdict Refiner::judge_sample(const SampleSet& set, std::size_t k, const glm::vec4& tested,
                                       bool on_boundary, float threshold) const {
  Verdict v;
  const SplitRequest& r = set.requests[k];
  const ElementShape shape = element_shape(s_, r);
  const glm::vec3 step = sample_step(set, k, tested);
  glm::vec3 interpolated(0.0f);
  const int n = r.kind == SplitRequest::kFace ? 3 : 2;
  for (int c = 0; c < n; ++c) {
    const std::uint32_t corner = r.kind == SplitRequest::kFace ? s_.faces[r.element][c] : s_.edges[r.element][c];
    if (corner < last_move_.size()) interpolated += r.weights[c] * last_move_[corner];
  }
  v.offset = element_offset(shape, step - interpolated);
  if (v.offset <= threshold) return v;
  // The full step overshoots where the new faces' extra area outweighs the weaker material
  // reached, so the move is backtracked along the step until it lowers E.
  const glm::vec3 p(set.points[k]);
  glm::vec3 d = step;
  for (int halving = 0; halving < kInsertBacktracks; ++halving, d *= 0.5f) {
    glm::vec3 q = p + d;
    if (on_boundary) q = glm::vec3(b_.closest_point(glm::dvec3(q)));
    if (split_delta_energy(s_, samples_, r, q, sample_field(field_, q).x) < 0.0) {
      v.split = true;
      return v;
    }
  }
  return v;
}

// conform_boundary's splits move each new vertex from its chord's midpoint onto B: that motion is
// checked like a flow step's, on a preview of S after the splits, and held-back splits dropped.
// Conforming comes before the first flow step, when no vertex's clearance is known yet: the trial
// has none to inherit, and keeps none (its other vertices stay put and need no inside test).
void Refiner::drop_colliding_insertions(std::vector<SplitRequest>& chosen, std::vector<glm::vec3>& start,
                                        std::vector<glm::vec3>& target) const {
  if (chosen.empty()) return;
  const std::size_t first_new = s_.positions.size();
  const FractureSurface trial = split_preview(s_, chosen, start, nullptr);
  std::vector<glm::vec4> x0 = trial.positions, x1 = trial.positions;
  for (std::size_t k = 0; k < chosen.size(); ++k) x1[first_new + k] = glm::vec4(target[k], 1.0f);
  apply_boundary_constraint(trial, b_, x0, x1);
  if (o_.collisions) apply_collision_constraints(trial, b_, x0, x1, nullptr);
  std::size_t kept = 0;
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    if (x1[first_new + k] != glm::vec4(target[k], 1.0f)) continue;  // held back: drop this split
    chosen[kept] = chosen[k], start[kept] = start[k], target[kept] = target[k];
    ++kept;
  }
  chosen.resize(kept), start.resize(kept), target.resize(kept);
}

// Distance to B is 1-Lipschitz, so a new vertex is at least (clearance of a parent − its distance
// from that parent) away from B: most new vertices need no closest-point query of their own.
// Vertices the cache does not cover yet (`clearance` shorter than S) get the best such bound.
void Refiner::inherit_clearance(const FractureSurface& s, const RefinementTree& tree, std::vector<float>& clearance) const {
  const std::size_t first_new = clearance.size();
  clearance.resize(s.positions.size(), -1.0f);
  for (std::size_t v = first_new; v < s.positions.size(); ++v) {
    if (s.vertex_flags[v] & kVertexBoundary) continue;
    double best = -1.0;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = tree.parents[v][k];
      if (tree.weights[v][k] == 0.0f || p >= first_new || clearance[p] < 0.0f) continue;
      const double gap = double(glm::distance(glm::dvec3(glm::vec3(s.positions[v])), glm::dvec3(glm::vec3(s.positions[p]))));
      best = std::max(best, (double(clearance[p]) - gap) * (1.0 - 1e-6));
    }
    clearance[v] = best > 0.0 ? float(best) : -1.0f;
  }
}

}  // namespace fracref::refine_detail
