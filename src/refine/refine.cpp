#include "refine/refine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "field/field_sampler.hpp"
#include "util/parallel.hpp"
#include "refine/collisions.hpp"
#include "refine/containment.hpp"
#include "refine/flips.hpp"
#include "refine/samples.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

// A vertex never moves more than this fraction of its shortest incident edge in one step, so a
// step cannot invert its triangles. The automatic time step is the median over vertices of
// kStepFraction · ℓ_i / |v_i|: half the vertices take the full gradient step, the fastest half
// are clipped to kStepFraction · ℓ_i (a normalised-gradient step). If the energy rises anyway
// the step is halved (at most kBacktracks times) and, failing that, not taken.
constexpr float kStepFraction = 0.3f;
// A vertex whose move is under this fraction of its shortest edge stays put (it has settled).
// On the bunny, 96% of the moving vertices carry 5% of a late step's squared motion (median move
// 0.27% of the shortest edge: stiff, nearly flat fans); holding those back leaves E within 0.1%
// and ζ unchanged, and keeps them out of the step's collision tests (resting pairs are skipped).
constexpr float kSettleFraction = 0.01f;
constexpr int kBacktracks = 6;
constexpr double kStiffFraction = 0.5;
constexpr int kInsertBacktracks = 10;
constexpr float kFillFraction = 0.25f;      // of tau: the smallest offset fill_budget splits
constexpr double kConformTolerance = 2e-4;  // of the diagonal
constexpr int kConformPasses = 8;
// Passes of split_rim_chords after the loop (a pass splits each face at most once).
constexpr int kChordPasses = 4;
// Threads judging the split samples (the verdicts do not depend on it).
constexpr int kThreads = 2;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

class Refiner {
 public:
  Refiner(FractureSurface& s, const FieldGrid4& field, const ExteriorSurface& b, ComputeBackend& be,
          const RefineOptions& o)
      : s_(s), field_(field), b_(b), be_(be), o_(o) {}

  RefineResult run(const RefineProgress& progress);

 private:
  SurfaceView view() const { return {s_.positions, s_.faces, s_.vf_offsets, s_.vf_faces}; }
  void evaluate();
  void sample_new_vertices();
  double energy() const { return surface_energy(view(), samples_); }
  std::vector<float> shortest_edges() const;
  float choose_dt(const std::vector<float>& shortest) const;
  std::vector<glm::vec3> boundary_tangents() const;
  std::vector<float> stiffness_steps() const;
  void conform_boundary();
  // Containment splits: lengths in the scene's unit, nothing split below the sample spacing.
  TuckOptions tuck_options() const { return {.scale = o_.scale, .min_edge = o_.delta}; }
  bool flow_step(double ceiling, IterationStats& st);
  std::size_t refine_step(std::uint32_t iteration);
  IterationStats iterate(std::uint32_t iteration, double e_before);
  struct ElementMotion {
    glm::vec3 sample{0.0f}, interpolated{0.0f};
  };
  struct Verdict {
    bool split = false;
    float offset = 0.0f;   // how far the judging step takes the sample off its element
    glm::vec3 move{0.0f};  // where the judging step takes the sample, from it
  };
  Verdict judge_sample(const SplitRequest& r, const glm::vec3& p, const glm::vec4& tested, bool on_boundary,
                       float threshold) const;
  // The splits chosen so far in an iteration (faces touched, within the budget).
  struct SplitChoice {
    std::vector<char> touched;
    std::vector<SplitRequest> chosen;
    std::vector<glm::vec3> start;
    std::size_t faces = 0;
    bool add(const FractureSurface& s, const SplitRequest& r, std::size_t max_faces, bool& over_budget);
  };
  void fill_budget(const SampleSet& set, const std::vector<glm::vec4>& tested, const std::vector<char>& on_boundary,
                   std::vector<Verdict>& verdicts, SplitChoice& choice);
  ElementMotion element_motion(const SplitRequest& r, const glm::vec3& v_sample, float shortest) const;
  void drop_colliding_insertions(std::vector<SplitRequest>& chosen, std::vector<glm::vec3>& start,
                                 std::vector<glm::vec3>& target) const;
  void inherit_clearance(const FractureSurface& s, const RefinementTree& tree, std::vector<float>& clearance) const;
  void shorten_clearance(const std::vector<glm::vec4>& full, const std::vector<glm::vec4>& at);

  FractureSurface& s_;
  const FieldGrid4& field_;
  const ExteriorSurface& b_;
  ComputeBackend& be_;
  RefineOptions o_;
  RefinementTree tree_;
  std::vector<glm::vec4> samples_, velocity_;
  bool budget_reached_ = false;   // a split was refused because it would exceed max_triangles
  std::vector<float> clearance_;  // per vertex, a lower bound of the distance to B (< 0: unknown)
  // The vertices the last splits inserted (ids from first_inserted_ on) and the moves that
  // judged them (see inserted_step).
  std::size_t first_inserted_ = 0;
  std::vector<glm::vec3> insertion_moves_;
  bool inserted_step(std::size_t v, float shortest, glm::vec3& d) const;
};

// The splits leave old vertices where they were: only the new ones need ψ (for the flips'
// energy test) before the evaluation that follows the flips. sample_field is the CPU backend's
// own sampling, and the Vulkan kernel's is bit-identical to it.
void Refiner::sample_new_vertices() {
  const std::size_t first = samples_.size();
  samples_.resize(s_.positions.size());
  for (std::size_t v = first; v < samples_.size(); ++v) samples_[v] = sample_field(field_, glm::vec3(s_.positions[v]));
}

void Refiner::evaluate() {
  samples_.resize(s_.positions.size());
  velocity_.resize(s_.positions.size());
  be_.vertex_velocities(view(), samples_, velocity_);
}

std::vector<float> Refiner::shortest_edges() const {
  std::vector<float> len(s_.positions.size(), std::numeric_limits<float>::max());
  for (const glm::uvec2& e : s_.edges) {
    float l = glm::distance(glm::vec3(s_.positions[e.x]), glm::vec3(s_.positions[e.y]));
    len[e.x] = std::min(len[e.x], l);
    len[e.y] = std::min(len[e.y], l);
  }
  return len;
}

// A boundary vertex slides on B; its motion ALONG the boundary curve changes nothing of the
// shape but bunches boundary vertices into slivers that no flip can repair (boundary edges are
// special), so it is removed: boundary vertices move only across the curve.
std::vector<glm::vec3> Refiner::boundary_tangents() const {
  std::vector<glm::vec3> first(s_.positions.size(), glm::vec3(0.0f)), tangent(s_.positions.size(), glm::vec3(0.0f));
  std::vector<std::uint8_t> count(s_.positions.size(), 0);
  for (std::uint32_t e = 0; e < s_.edges.size(); ++e) {
    if (s_.edge_special[e] != kEdgeBoundary) continue;
    glm::uvec2 ab = s_.edges[e];
    glm::vec3 dir = glm::vec3(s_.positions[ab.y]) - glm::vec3(s_.positions[ab.x]);
    float len = glm::length(dir);
    if (len == 0.0f) continue;
    dir /= len;
    for (std::uint32_t v : {ab.x, ab.y}) {
      if (count[v]++ == 0) first[v] = dir;
      else if (count[v] == 2) tangent[v] = glm::dot(first[v], dir) >= 0.0f ? first[v] + dir : first[v] - dir;
    }
  }
  for (std::size_t v = 0; v < tangent.size(); ++v) {
    float len = glm::length(tangent[v]);
    tangent[v] = (count[v] == 2 && len > 0.0f) ? tangent[v] / len : glm::vec3(0.0f);
  }
  return tangent;
}

// The area term of the flow is stiff: a vertex of a sliver or of a small tent has a huge
// velocity and an explicit step overshoots it into oscillation. Moving vertex i out of the plane
// of face j (opposite edge L_j, area A_j) by h adds ½ h² L_j²/(4 A_j) to the area, so the energy's
// normal stiffness at i is H_i = ψ_i Σ_j L_j²/(4 A_j) and the Newton step for it is M_i / H_i.
// Each vertex's step is capped at kStiffFraction of it: a Jacobi-preconditioned descent.
std::vector<float> Refiner::stiffness_steps() const {
  // The faces' terms side by side, summed per vertex in face order (the same doubles as a
  // serial loop); a degenerate face adds nothing.
  std::vector<glm::dvec3> term(s_.faces.size());
  parallel_chunks(term.size(), chunk_count(term.size(), 4096), kThreads, [&](std::size_t, std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) {
      const glm::uvec4 f = s_.faces[j];
      glm::dvec3 x[3] = {glm::dvec3(glm::vec3(s_.positions[f.x])), glm::dvec3(glm::vec3(s_.positions[f.y])),
                         glm::dvec3(glm::vec3(s_.positions[f.z]))};
      double area = 0.5 * glm::length(glm::cross(x[1] - x[0], x[2] - x[0]));
      term[j] = glm::dvec3(0.0);
      if (area <= 0.0) continue;
      for (int k = 0; k < 3; ++k) {
        glm::dvec3 opposite = x[(k + 2) % 3] - x[(k + 1) % 3];
        term[j][k] = glm::dot(opposite, opposite) / (4.0 * area);
      }
    }
  });
  std::vector<double> h(s_.positions.size(), 0.0);
  for (std::size_t j = 0; j < term.size(); ++j)
    for (int k = 0; k < 3; ++k) h[s_.faces[j][k]] += term[j][k];
  std::vector<float> out(h.size(), std::numeric_limits<float>::max());
  for (std::size_t i = 0; i < h.size(); ++i) {
    double stiffness = std::max(double(samples_[i].x), 1e-6) * h[i];
    if (stiffness > 0.0) out[i] = float(kStiffFraction * velocity_[i].w / stiffness);
  }
  return out;
}

float Refiner::choose_dt(const std::vector<float>& shortest) const {
  if (o_.step > 0.0) return float(o_.step);
  std::vector<float> ratios;
  ratios.reserve(velocity_.size());
  for (std::size_t i = 0; i < velocity_.size(); ++i) {
    float speed = glm::length(glm::vec3(velocity_[i]));
    if (speed > 0.0f && shortest[i] < std::numeric_limits<float>::max())
      ratios.push_back(kStepFraction * shortest[i] / speed);
  }
  if (ratios.empty()) return 0.0f;
  auto mid = ratios.begin() + ratios.size() / 2;
  std::nth_element(ratios.begin(), mid, ratios.end());
  return *mid;
}

// A vertex inserted by the last splits takes, in the flow step after them, the move that judged
// its split (over its element's time scale, which the global step does not give it: with the
// global step refinement slowed, the branch took 13 iterations instead of 10). Near B it takes
// the ordinary step: boundary vertices and vertices within a few steps of B moved that far left
// slivers along the rim that made the pieces stage retry (bunny: 13 attempts instead of 7).
bool Refiner::inserted_step(std::size_t v, float shortest, glm::vec3& d) const {
  if (v < first_inserted_ || v - first_inserted_ >= insertion_moves_.size()) return false;
  if ((s_.vertex_flags[v] & kVertexBoundary) || !(clearance_[v] > 4.0f * kStepFraction * shortest)) return false;
  d = insertion_moves_[v - first_inserted_];
  return true;
}

// Takes the step when it brings E to at most `ceiling` (backtracking as above) and sets st.energy
// to the new E; false when no step does, S then unchanged.
// \pre samples_ and velocity_ are those of the current positions (run() evaluates after every
// edit; each evaluation is a kernel call, with a fixed cost on Vulkan).
bool Refiner::flow_step(double ceiling, IterationStats& st) {
  const double e0 = ceiling;
  const std::vector<float> shortest = shortest_edges();
  const std::vector<glm::vec3> boundary_tangent = boundary_tangents();
  const std::vector<float> stiff_dt = stiffness_steps();
  float dt = choose_dt(shortest);
  const std::vector<glm::vec4> x0 = s_.positions;
  std::vector<glm::vec4> full = x0;
  for (std::size_t i = 0; i < x0.size(); ++i) {
    glm::vec3 d = std::min(dt, stiff_dt[i]) * glm::vec3(velocity_[i]);
    d -= glm::dot(d, boundary_tangent[i]) * boundary_tangent[i];
    inserted_step(i, shortest[i], d);
    float len = glm::length(d), cap = kStepFraction * shortest[i];
    if (len > cap) d *= cap / len;
    if (len < kSettleFraction * shortest[i]) d = glm::vec3(0.0f);
    full[i] = glm::vec4(glm::vec3(x0[i]) + d, 1.0f);
  }
  apply_boundary_constraint(s_, b_, x0, full);
  const auto t_ccd = Clock::now();
  st.collisions_stopped = o_.collisions ? apply_collision_constraints(s_, b_, x0, full, &clearance_) : 0;
  st.phases.flow_collisions = seconds_since(t_ccd);
  // Backtracking shortens the constrained, collision-free motion: every vertex then follows the
  // first part of the same straight path, which is collision-free too (boundary vertices are
  // projected back onto B, a deviation of second order in the step).
  float fraction = 1.0f;
  for (int attempt = 0; attempt <= kBacktracks; ++attempt, fraction *= 0.5f) {
    std::vector<glm::vec4> x1 = x0;
    for (std::size_t i = 0; i < x0.size(); ++i) x1[i] = x0[i] + fraction * (full[i] - x0[i]);
    if (attempt > 0) apply_boundary_constraint(s_, b_, x0, x1);
    s_.positions = x1;
    std::vector<glm::vec4> trial(x1.size()), vel(x1.size());
    be_.vertex_velocities(view(), trial, vel);
    if (const double e1 = surface_energy(view(), trial); e1 <= e0) {
      st.energy = e1;
      st.dt = dt * fraction;
      for (std::size_t i = 0; i < x0.size(); ++i)
        st.max_displacement = std::max<double>(st.max_displacement, glm::distance(glm::vec3(x0[i]), glm::vec3(x1[i])));
      samples_ = std::move(trial);
      velocity_ = std::move(vel);
      shorten_clearance(full, x1);
      return true;
    }
  }
  s_.positions = x0;  // no step lowered the energy: stay (samples_ and velocity_ are x0's still)
  shorten_clearance(full, x0);
  return false;
}

// The collision constraints left clearance_ as bounds at `full`; a vertex that ends elsewhere on
// its path (a shortened or refused step) is at least that bound minus the gap away from B.
void Refiner::shorten_clearance(const std::vector<glm::vec4>& full, const std::vector<glm::vec4>& at) {
  for (std::size_t i = 0; i < at.size(); ++i) {
    if (clearance_[i] < 0.0f || full[i] == at[i]) continue;
    const double gap = glm::distance(glm::dvec3(glm::vec3(full[i])), glm::dvec3(glm::vec3(at[i])));
    const double bound = (double(clearance_[i]) - gap) * (1.0 - 1e-6);
    clearance_[i] = bound > 0.0 ? float(bound) : -1.0f;
  }
}

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

// A sample whose flow step would take it too far from its element (paper 4.4: "if it moves too
// far away from the triangle after one iteration, we add it as a new vertex") is inserted where it
// lies, when moving it where the step would take it lowers the energy. The tree records its
// weights on the parent element (its position at creation). Inserting it on its element leaves
// the shape as it was, so no collision test is needed here: the flow step that follows moves the
// new vertices with all the others, under the same collision constraints. (A boundary sample
// lies on B, off its edge's chord: that jump is not tested, as the rim chords are not.)
std::size_t Refiner::refine_step(std::uint32_t iteration) {
  const float scale = float(o_.scale);
  SampleSet set = draw_samples(s_, o_.seed, iteration, float(o_.delta) * scale);
  std::vector<char> on_boundary(set.points.size(), 0);
  parallel_chunks(set.points.size(), chunk_count(set.points.size(), 4096), kThreads,
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
  parallel_chunks(set.points.size(), chunk_count(set.points.size(), 1024), kThreads,
                  [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t k = begin; k < end; ++k)
                      verdicts[k] =
                          judge_sample(set.requests[k], glm::vec3(set.points[k]), out[k], on_boundary[k], tau);
                  });
  SplitChoice choice;
  choice.touched.assign(s_.faces.size(), 0);
  choice.faces = s_.faces.size();
  first_inserted_ = s_.positions.size();
  insertion_moves_.clear();
  for (std::size_t k = 0; k < set.points.size() && !budget_reached_; ++k) {
    if (!verdicts[k].split || !choice.add(s_, set.requests[k], o_.max_triangles, budget_reached_)) continue;
    choice.start.push_back(glm::vec3(set.points[k]));
    insertion_moves_.push_back(verdicts[k].move);
  }
  if (o_.fill_budget && !budget_reached_) fill_budget(set, out, on_boundary, verdicts, choice);
  std::vector<SplitRequest>& chosen = choice.chosen;
  std::vector<glm::vec3>& start = choice.start;
  apply_splits(s_, tree_, chosen, &start);
  inherit_clearance(s_, tree_, clearance_);
  return chosen.size();
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

// When the next iteration, growing S as this one does, would run into the budget, it would cost
// a pass over all of S for what is left of the budget: that room is filled now instead, with the
// samples below τ (down to kFillFraction τ) that would move farthest, largest offset first. On
// the bunny this spares the last and costliest of its iterations.
void Refiner::fill_budget(const SampleSet& set, const std::vector<glm::vec4>& tested,
                          const std::vector<char>& on_boundary, std::vector<Verdict>& verdicts, SplitChoice& choice) {
  const double before = double(s_.faces.size()), after = double(choice.faces);
  if (!(after > before) || after * (after / before) < double(o_.max_triangles)) return;
  const float tau = float(o_.tau) * float(o_.scale), floor = kFillFraction * tau;
  std::vector<std::uint32_t> order;
  // Samples above τ that were not split failed the energy test already: judged again, they would again.
  for (std::uint32_t k = 0; k < verdicts.size(); ++k)
    if (!verdicts[k].split && verdicts[k].offset > floor && verdicts[k].offset <= tau) order.push_back(k);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return verdicts[a].offset > verdicts[b].offset || (verdicts[a].offset == verdicts[b].offset && a < b);
  });
  parallel_chunks(
      order.size(), chunk_count(order.size(), 1024), kThreads, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          const std::uint32_t k = order[i];
          verdicts[k] = judge_sample(set.requests[k], glm::vec3(set.points[k]), tested[k], on_boundary[k], floor);
        }
      });
  for (std::size_t i = 0; i < order.size() && !budget_reached_; ++i) {
    const std::uint32_t k = order[i];
    if (!verdicts[k].split || !choice.add(s_, set.requests[k], o_.max_triangles, budget_reached_)) continue;
    choice.start.push_back(glm::vec3(set.points[k]));
    insertion_moves_.push_back(verdicts[k].move);
  }
}

// Each sample is judged over its own element's time scale: the step that moves the element's
// fastest point (the sample or a corner) by kStepFraction of the element's shortest edge. Its
// distance from the moved element is its motion relative to the motion the corners interpolate
// to at the sample: zero where ψ is linear over the element, so elements split where the field
// has detail at their size, and refinement stops once ψ is linear at τ.
Refiner::Verdict Refiner::judge_sample(const SplitRequest& r, const glm::vec3& p, const glm::vec4& tested,
                                       bool on_boundary, float threshold) const {
  Verdict v;
  const ElementShape shape = element_shape(s_, r);
  const ElementMotion m = element_motion(r, glm::vec3(tested), shape.shortest);
  v.offset = element_offset(shape, m.sample - m.interpolated);
  if (v.offset <= threshold) return v;
  // The full step overshoots where the new faces' extra area outweighs the weaker material
  // reached, so the move is backtracked along the step until it lowers E.
  glm::vec3 d = m.sample;
  for (int halving = 0; halving < kInsertBacktracks; ++halving, d *= 0.5f) {
    glm::vec3 q = p + d;
    if (on_boundary) q = glm::vec3(b_.closest_point(glm::dvec3(q)));
    if (split_delta_energy(s_, samples_, r, q, sample_field(field_, q).x) < 0.0) {
      v.split = true;
      v.move = q - p;
      return v;
    }
  }
  return v;
}

Refiner::ElementMotion Refiner::element_motion(const SplitRequest& r, const glm::vec3& v_sample, float shortest) const {
  glm::uvec3 corners(0u);
  int n = 3;
  if (r.kind == SplitRequest::kFace) corners = glm::uvec3(s_.faces[r.element]);
  else corners = glm::uvec3(s_.edges[r.element], 0u), n = 2;
  float fastest = glm::length(v_sample);
  for (int c = 0; c < n; ++c) fastest = std::max(fastest, glm::length(glm::vec3(velocity_[corners[c]])));
  ElementMotion m;
  if (!(fastest > 0.0f)) return m;
  float dt = kStepFraction * shortest / fastest;
  m.sample = dt * v_sample;
  for (int c = 0; c < n; ++c) m.interpolated += r.weights[c] * dt * glm::vec3(velocity_[corners[c]]);
  return m;
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

// The pieces stage traces every boundary edge of S across B; a long boundary edge whose chord
// cuts deep under a curved B traces a path far from its chord, and neighbouring traces can cross.
// Before the flow starts, boundary edges are split at their midpoint projected onto B until every
// chord is within kConformTolerance of B.
void Refiner::conform_boundary() {
  const double limit = kConformTolerance * o_.scale;
  for (int pass = 0; pass < kConformPasses; ++pass) {
    std::vector<SplitRequest> chosen;
    std::vector<glm::vec3> start, target;
    std::vector<char> touched(s_.faces.size(), 0);
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e) {
      if (s_.edge_special[e] != kEdgeBoundary) continue;
      std::uint32_t f = s_.ef_faces[s_.ef_offsets[e]];
      if (touched[f]) continue;
      glm::uvec2 ab = s_.edges[e];
      glm::dvec3 mid = 0.5 * (glm::dvec3(glm::vec3(s_.positions[ab.x])) + glm::dvec3(glm::vec3(s_.positions[ab.y])));
      glm::dvec3 q = b_.closest_point(mid);
      if (glm::distance(q, mid) <= limit) continue;
      touched[f] = 1;
      chosen.push_back({SplitRequest::kEdge, e, glm::vec3(0.5f, 0.5f, 0.0f)});
      start.push_back(glm::vec3(mid));
      target.push_back(glm::vec3(q));
    }
    if (chosen.empty()) return;
    drop_colliding_insertions(chosen, start, target);
    if (chosen.empty()) return;
    apply_splits(s_, tree_, chosen, &target);
  }
}

// Splits, flips, then one flow step that moves the new vertices with the others. The splits may
// raise E a little (ψ at a sample is not the interpolation of its corners'), so the step must
// bring E to at most `e_before`, the energy the iteration started at; when no step does, the
// iteration's splits and flips are undone and S stays as it was. The step itself must lower E
// from where the splits left it, as any descent step.
IterationStats Refiner::iterate(std::uint32_t it, double e_before) {
  IterationStats st;
  const auto t0 = Clock::now();
  const FractureSurface s_before = s_;
  const std::vector<glm::vec4> samples_before = samples_, velocity_before = velocity_;
  st.splits = refine_step(it);
  sample_new_vertices();
  st.phases.splits = seconds_since(t0);
  auto t1 = Clock::now();
  st.flips = flip_slim_triangles(s_, samples_, b_, FlipOptions{o_.min_angle});
  st.phases.flips = seconds_since(t1);
  t1 = Clock::now();
  if (st.splits + st.flips > 0) evaluate();
  st.phases.evaluate = seconds_since(t1);
  t1 = Clock::now();
  const double e_now = energy();
  const bool moved = flow_step(std::min(e_before, e_now), st);
  st.phases.flow = seconds_since(t1);
  if (!moved) st.energy = e_now;
  if (!moved && e_now > e_before) {
    s_ = s_before;
    samples_ = samples_before, velocity_ = velocity_before;
    tree_.parents.resize(s_.positions.size()), tree_.weights.resize(s_.positions.size());
    clearance_.resize(s_.positions.size());
    st.splits = st.flips = 0;
    st.energy = e_before;  // S is the one e_before was measured on
  }
  st.triangles = s_.faces.size();
  st.seconds = seconds_since(t0);
  return st;
}

RefineResult Refiner::run(const RefineProgress& progress) {
  RefineResult result;
  tree_ = RefinementTree::identity(s_.positions.size());
  be_.set_field(field_);
  project_boundary_vertices(s_, b_);
  conform_boundary();
  tuck_inside(s_, tree_, b_, tuck_options());
  evaluate();
  result.initial_energy = energy();
  double e = result.initial_energy;
  for (int it = 0; it < o_.max_iterations; ++it) {
    IterationStats st = iterate(std::uint32_t(it), e);
    e = st.energy;
    result.iterations.push_back(st);
    if (progress) progress(st, it, o_.max_iterations);
    // Once a split has been refused for the budget, the surface is within one split of it:
    // further iterations would add a handful of faces each at the full cost of an iteration.
    const double room = double(o_.max_triangles) - double(s_.faces.size());
    if (budget_reached_ || room < o_.budget_slack * double(o_.max_triangles)) {
      result.stop = RefineResult::Stop::kTriangleBudget;
      break;
    }
    if (st.splits == 0 && st.max_displacement < o_.tolerance * o_.scale) {
      result.stop = RefineResult::Stop::kConverged;
      break;
    }
  }
  split_rim_chords(s_, tree_, b_, tuck_options(), kChordPasses);
  // Every edit is meant to keep S valid; a violation here is a bug, and it must not reach the
  // pieces or the output files silently. The derived arrays are the incremental rebuilds' (which
  // the unit tests compare with fresh ones): comparing them with a fresh rebuild here would cost
  // a full rebuild.
  if (std::string broken = validate_rebuilt(s_); !broken.empty())
    throw RunError("refinement produced an invalid fracture surface (an internal error; please report it): " + broken);
  result.tree = std::move(tree_);
  return result;
}

}  // namespace

RefineResult refine_surface(FractureSurface& s, const FieldGrid4& field, const ExteriorSurface& exterior,
                            ComputeBackend& backend, const RefineOptions& options, const RefineProgress& progress) {
  Refiner r(s, field, exterior, backend, options);
  return r.run(progress);
}

}  // namespace fracref
