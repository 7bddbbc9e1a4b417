#include "refine/refine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "field/field_sampler.hpp"
#include "geom/predicates.hpp"
#include "flow/implicit_step.hpp"
#include "util/parallel.hpp"
#include "refine/collisions.hpp"
#include "refine/containment.hpp"
#include "refine/flips.hpp"
#include "refine/junction_order.hpp"
#include "refine/exterior_contact.hpp"
#include "refine/motion_filters.hpp"
#include "refine/rim_collar.hpp"
#include "refine/samples.hpp"
#include "refine/step_guard.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

// The flow step (flow/implicit_step.hpp) is semi-implicit: its length is set by the scene, not
// by the smallest triangle. dt = step · scale / g, g the root mean square of |∇ψ| over the field's
// nodes: at the field's typical gradient a vertex is driven `step` of the diagonal per iteration.
// If the energy rises the step is halved (at most kBacktracks times) and, failing that, not taken.
constexpr double kDefaultStep = 0.004;
constexpr int kBacktracks = 6;
constexpr int kInsertBacktracks = 10;
// Converged after this many iterations in a row that lower E by less than the tolerance.
constexpr int kCalmIterations = 2;
constexpr double kConformTolerance = 2e-4;  // of the diagonal
constexpr int kConformPasses = 8;
// Passes of split_rim_chords after the loop (a pass splits each face at most once).
constexpr int kChordPasses = 4;
// Barycentric weights below this are zeroed where a rim vertex slides on B (Refiner::slid_rim).
constexpr double kSlideSnap = 1e-3;
// Threads judging the split samples (the verdicts do not depend on it).

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

class Refiner {
 public:
  Refiner(FractureSurface& s, const FieldGrid4& field, const ExteriorSurface& b, ComputeBackend& be,
          const RefineOptions& o)
      : s_(s), field_(field), b_(b), be_(be), o_(o) {
    if (b.mesh.triangles.empty()) {
      MeshSoup soup;
      soup.positions = b.bvh.positions;
      soup.triangles = b.bvh.triangles;
      own_mesh_ = rim::make_exterior_mesh(soup);
    }
  }

  RefineResult run(const RefineProgress& progress);

 private:
  SurfaceView view() const { return {s_.positions, s_.faces, s_.vf_offsets, s_.vf_faces}; }
  void evaluate();
  void sample_new_vertices();
  double energy() const { return surface_energy(view(), samples_); }
  StepGuardOptions step_guard_options() const;
  void conform_boundary();
  const rim::ExteriorMesh& mesh() const { return b_.mesh.triangles.empty() ? own_mesh_ : b_.mesh; }
  void embed_rim();
  void reembed_rim();
  rim::RimOnB slid_rim(const std::vector<glm::vec4>& x) const;
  void snap_slid_rim(std::vector<glm::vec4>& x) const;
  std::vector<std::uint32_t> rim_runs_past_rim_points(const rim::RimOnB& rim) const;
  std::vector<std::uint32_t> rim_segments_crossing(const rim::RimOnB& rim) const;
  std::size_t hold_rim_degeneracies(const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1) const;
  void locate_new_rim_vertices();
  std::vector<std::uint32_t> flagged_faces(const std::vector<glm::vec4>& x, const std::vector<float>& clearance) const;
  std::vector<std::uint32_t> new_crossings(const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1,
                                           const std::vector<float>& clearance) const;
  std::size_t hold_exterior_crossings(const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1,
                                      const std::vector<float>& clearance) const;
  // Containment splits: lengths in the scene's unit, nothing split below the sample spacing.
  TuckOptions tuck_options() const { return {.scale = o_.scale, .min_edge = o_.delta}; }
  bool flow_step(double start, double ceiling, IterationStats& st);
  std::size_t refine_step(std::uint32_t iteration, bool propagate, std::size_t& graded);
  SplitRequest bisection(const SplitRequest& r, bool propagate, glm::vec3& start, bool& path_left) const;
  IterationStats iterate(std::uint32_t iteration, double e_before);
  IterationStats attempt(std::uint32_t iteration, double e_before, bool graded, bool& undone);
  struct Verdict {
    bool split = false;
    float offset = 0.0f;  // how far the step takes the sample off its element
  };
  Verdict judge_sample(const SampleSet& set, std::size_t k, const glm::vec4& tested, bool on_boundary,
                       float threshold) const;
  // The splits chosen so far in an iteration (faces touched, within the budget).
  struct SplitChoice {
    std::vector<char> touched;
    std::vector<SplitRequest> chosen;
    std::vector<glm::vec3> start;
    std::vector<char> graded;  // per chosen split: its longest-edge path left the sample's element
    std::size_t faces = 0;
    bool add(const FractureSurface& s, const SplitRequest& r, std::size_t max_faces, bool& over_budget);
  };
  void drop_crossing_splits(SplitChoice& choice) const;
  glm::vec3 sample_step(const SampleSet& set, std::size_t k, const glm::vec4& tested) const;
  void drop_colliding_insertions(std::vector<SplitRequest>& chosen, std::vector<glm::vec3>& start,
                                 std::vector<glm::vec3>& target) const;
  void inherit_clearance(const FractureSurface& s, const RefinementTree& tree, std::vector<float>& clearance) const;
  void inherit_moves();
  void shorten_clearance(const std::vector<glm::vec4>& full, const std::vector<glm::vec4>& at);

  FractureSurface& s_;
  const FieldGrid4& field_;
  const ExteriorSurface& b_;
  ComputeBackend& be_;
  RefineOptions o_;
  rim::ExteriorMesh own_mesh_;  // B's mesh when the ExteriorSurface came without one
  rim::RimOnB rim_;             // where S's rim vertices lie on B (rim/rim_on_b.hpp)
  RefinementTree tree_;
  std::vector<glm::vec4> samples_, velocity_;
  double dt_ = 0.0;               // the flow's time step (see kDefaultStep)
  bool budget_reached_ = false;   // a split was refused because it would exceed max_triangles
  std::vector<float> clearance_;  // per vertex, a lower bound of the distance to B (< 0: unknown)
  std::vector<glm::vec3> last_move_;  // per vertex, its motion in the last flow step
  bool flow_moved_ = true;            // whether the last flow step moved S
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

// B's normal at the middle of each rim face's boundary edge (step_guard.hpp).
StepGuardOptions Refiner::step_guard_options() const {
  StepGuardOptions g;
  g.rim_normals.assign(s_.faces.size(), glm::dvec3(0.0));
  for (std::uint32_t e = 0; e < s_.edges.size(); ++e) {
    if (s_.edge_special[e] != kEdgeBoundary) continue;
    const glm::uvec2 ab = s_.edges[e];
    const glm::dvec3 mid = 0.5 * (glm::dvec3(glm::vec3(s_.positions[ab.x])) + glm::dvec3(glm::vec3(s_.positions[ab.y])));
    g.rim_normals[s_.ef_faces[s_.ef_offsets[e]]] = b_.normal(closest_point(b_.bvh, mid).triangle);
  }
  return g;
}

// Takes the step when it brings E to at most `ceiling` (backtracking as above) and sets st.energy
// to the new E; false when no step does, S then unchanged. `start` is E at the current positions.
// \pre samples_ and velocity_ are those of the current positions (run() evaluates after every
// edit; each evaluation is a kernel call, with a fixed cost on Vulkan).
bool Refiner::flow_step(double start, double ceiling, IterationStats& st) {
  const double e0 = ceiling;
  const std::vector<glm::dmat3> filter = motion_filters(
      s_, b_, {.rim_motion = o_.rim_motion, .tangential = o_.tangential_motion, .threads = default_threads()});
  std::vector<glm::dvec3> d(s_.positions.size());
  for (std::size_t i = 0; i < d.size() && i < last_move_.size(); ++i) d[i] = glm::dvec3(last_move_[i]);
  st.solver_iterations = implicit_step(view(), samples_, velocity_, dt_, filter, d, {.threads = default_threads()}).iterations;
  const std::vector<glm::vec4> x0 = s_.positions;
  std::vector<glm::vec4> full = x0;
  for (std::size_t i = 0; i < x0.size(); ++i) full[i] = glm::vec4(glm::vec3(x0[i]) + glm::vec3(d[i]), 1.0f);
  // A face the contact rule flags at x0 already must not move (new_crossings): its corners stay
  // in the full step, and so in every shorter one. Held only where the full step leaves it
  // flagged, a face that the full step frees holds back every shorter step, which still flags it.
  for (const std::uint32_t f : flagged_faces(x0, clearance_))
    for (int k = 0; k < 3; ++k) full[s_.faces[f][k]] = x0[s_.faces[f][k]];
  apply_boundary_constraint(s_, b_, x0, full);
  if (o_.rim_motion) {
    snap_slid_rim(full);
    hold_rim_degeneracies(x0, full);
  }
  const StepGuardOptions guard = step_guard_options();
  hold_folding_motion(s_, x0, full, guard);
  const auto t_ccd = Clock::now();
  const std::vector<float> clearance_x0 = clearance_;
  StepCollisions collisions(s_, b_, x0);
  st.collisions_stopped = o_.collisions ? collisions.apply(full, &clearance_) : 0;
  // Vertices the collisions held can fold a face the guard passed; holding more of them cannot
  // make a collision, but it can expose one (collisions.hpp), so the collisions run again (from
  // the clearances at x0, which they take).
  while (o_.collisions && hold_folding_motion(s_, x0, full, guard) > 0) {
    clearance_ = clearance_x0;
    st.collisions_stopped += collisions.apply(full, &clearance_);
  }
  std::vector<float> bound;
  auto bounds = [&] {
    bound.resize(clearance_.size());
    for (std::size_t i = 0; i < bound.size(); ++i)
      bound[i] = i < clearance_x0.size() ? std::min(clearance_[i], clearance_x0[i]) : clearance_[i];
  };
  bounds();
  // Holding the vertices of faces that would cross B, or of stars whose faces would cross each
  // other (the collisions skip faces that share a vertex), can expose a collision of S with itself
  // as holding for the collisions can (see above): the collisions run again, and so on until none
  // holds anything more (each round only holds vertices, so it ends).
  for (;;) {
    const std::size_t held = hold_exterior_crossings(x0, full, bound) + hold_star_crossings(s_, x0, full);
    st.collisions_stopped += held;
    if (held == 0 || !o_.collisions) break;
    clearance_ = clearance_x0;
    std::size_t more = collisions.apply(full, &clearance_);
    while (hold_folding_motion(s_, x0, full, guard) > 0) {
      clearance_ = clearance_x0;
      more += collisions.apply(full, &clearance_);
    }
    st.collisions_stopped += more;
    bounds();
    if (more == 0) break;
  }
  st.phases.flow_collisions = seconds_since(t_ccd);
  // Backtracking shortens the constrained, collision-free motion: every vertex then follows the
  // first part of the same straight path, which is collision-free too (boundary vertices are
  // projected back onto B, a deviation of second order in the step).
  // Where the splits raised E above the ceiling (start > ceiling), a shorter step tends to
  // `start`, above the ceiling: once halving the step raises E, E is on its way back up there, and
  // the shorter steps are not tried (they cost a velocity and energy evaluation each). Nor are
  // they once two lengths in a row say that E rises along the step at first order
  // (rises_at_first_order): where ψ's gradient is the pyramid's mean, not the base level's, the
  // step can point uphill for E, and then no shorter step lowers it.
  float fraction = 1.0f;
  double last = std::numeric_limits<double>::infinity();
  double rise_before = -1.0;  // E − start at the length before, when it was evaluated
  for (int attempt = 0; attempt <= kBacktracks; ++attempt, fraction *= 0.5f) {
    std::vector<glm::vec4> x1 = x0;
    for (std::size_t i = 0; i < x0.size(); ++i) x1[i] = x0[i] + fraction * (full[i] - x0[i]);
    if (attempt > 0) apply_boundary_constraint(s_, b_, x0, x1);
    if (o_.rim_motion) {
      snap_slid_rim(x1);
      std::vector<glm::vec4> held = x1;
      if (hold_rim_degeneracies(x0, held) > 0) continue;
    }
    const double rise_double = rise_before;
    rise_before = -1.0;
    if (attempt > 0 && (motion_folds(s_, x0, x1, guard) || motion_crosses_stars(s_, x0, x1))) continue;
    if (attempt > 0 && !new_crossings(x0, x1, bound).empty()) continue;
    s_.positions = x1;
    std::vector<glm::vec4> trial(x1.size()), vel(x1.size());
    be_.vertex_velocities(view(), trial, vel);
    const double e1 = surface_energy(view(), trial);
    if (e1 > e0 && start > e0 && e1 >= last) break;
    if (e1 > e0 && rises_at_first_order(rise_double, e1 - start)) break;
    last = e1;
    rise_before = e1 - start;
    if (e1 <= e0) {
      st.energy = e1;
      st.dt = dt_ * fraction;
      last_move_.resize(x0.size());
      for (std::size_t i = 0; i < x0.size(); ++i) {
        last_move_[i] = glm::vec3(x1[i]) - glm::vec3(x0[i]);
        st.max_displacement = std::max<double>(st.max_displacement, glm::length(last_move_[i]));
      }
      samples_ = std::move(trial);
      velocity_ = std::move(vel);
      shorten_clearance(full, x1);
      if (o_.rim_motion) rim_ = slid_rim(x1);
      return true;
    }
  }
  s_.positions = x0;  // no step lowered the energy: stay (samples_ and velocity_ are x0's still)
  std::fill(last_move_.begin(), last_move_.end(), glm::vec3(0.0f));
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

// The faces the contact rule (refine/exterior_contact.hpp) flags at positions x, the rim where
// x puts it.
std::vector<std::uint32_t> Refiner::flagged_faces(const std::vector<glm::vec4>& x, const std::vector<float>& clearance) const {
  return o_.rim_motion ? faces_crossing_exterior(s_, x, mesh(), slid_rim(x), clearance)
                       : faces_crossing_exterior(s_, x, mesh(), rim_, clearance);
}

// The faces that meet B at x1 other than at their rim points (refine/exterior_contact.hpp) and
// have a corner that moved from x0.
std::vector<std::uint32_t> Refiner::new_crossings(const std::vector<glm::vec4>& x0, const std::vector<glm::vec4>& x1,
                                                  const std::vector<float>& clearance) const {
  std::vector<std::uint32_t> bad = flagged_faces(x1, clearance);
  // A face the rule flags at x0 already (it is conservative where a rim point lies on a concave
  // B edge: the face is inside B but not inside both planes) must not move either: the rule could
  // not tell when it goes through B. So every flagged face with a moved corner counts.
  std::vector<std::uint32_t> moved;
  for (std::uint32_t f : bad) {
    const glm::uvec4 t = s_.faces[f];
    if (x1[t.x] != x0[t.x] || x1[t.y] != x0[t.y] || x1[t.z] != x0[t.z]) moved.push_back(f);
  }
  return moved;
}

// S meets B only at its rim: the vertices of a face the step would take across B stay at x0,
// until no new crossing is left (with every vertex held, S is x0's).
std::size_t Refiner::hold_exterior_crossings(const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1,
                                             const std::vector<float>& clearance) const {
  std::size_t held = 0;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::uint32_t f : new_crossings(x0, x1, clearance))
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = s_.faces[f][k];
        if (x1[v] == x0[v]) continue;
        x1[v] = x0[v];
        ++held;
        changed = true;
      }
  }
  return held;
}

// S's rim is embedded in B once, after the conforming splits (fewer traces to walk), and S is
// trimmed to B there (rim/trim_to_exterior.hpp): from then on a rim edge is only split at a point
// of its own segment, in the same triangle of B, and the contact rule keeps S's faces off B.
void Refiner::embed_rim() {
  // With rim_motion the rim vertices keep the locations they slid to (rim::EmbedOptions::known).
  rim::EmbedOptions eo;
  if (o_.rim_motion && !rim_.on_b.empty()) eo.known = &rim_;
  rim::Embedding e = rim::embed_rim(s_, mesh(), eo);
  for (const rim::EmbeddedVertex& a : e.added) {
    tree_.parents.push_back(glm::uvec3(a.parents[0], a.parents[1], a.parents[2]));
    tree_.weights.push_back(glm::vec3(a.weights));
  }
  rim_ = std::move(e.rim);
}

// With rim_motion the flow slides rim vertices on B (apply_boundary_constraint projects them);
// each keeps a location: where it lands on B (its closest point). A weight below kSlideSnap is
// zeroed, so a vertex that slides a hair past a B edge stays on it: otherwise the rim edge to it
// would be split a hair from its end (reembed_rim), a near-duplicate vertex.
// \pre x of S's vertices, rim vertices on B.
rim::RimOnB Refiner::slid_rim(const std::vector<glm::vec4>& x) const {
  rim::RimOnB out = rim_;
  for (std::size_t v = 0; v < x.size() && v < out.on_b.size(); ++v) {
    if (!out.on_b[v] || glm::vec3(x[v]) == glm::vec3(out.at[v].point)) continue;
    double distance = 0.0;
    out.at[v] = rim::locate_on_exterior(mesh(), glm::dvec3(glm::vec3(x[v])), kSlideSnap, &distance);
  }
  return out;
}

// Rim vertices of x moved to their slid locations (slid_rim), so that S's positions, the contact
// rule and the pieces see the same rim.
void Refiner::snap_slid_rim(std::vector<glm::vec4>& x) const {
  const rim::RimOnB slid = slid_rim(x);
  for (std::size_t v = 0; v < x.size() && v < slid.on_b.size(); ++v)
    if (slid.on_b[v]) x[v] = glm::vec4(glm::vec3(slid.at[v].point), 1.0f);
}

// The rim vertices of rim edges that run along a B edge (both ends on it) past another rim point
// on that edge, with the rim at `rim`: the pieces stage cuts B along the rim and cannot order
// such a segment among the points on its edge. A slide makes one where the rim folds back along
// a B edge, two rim edges of one vertex snapped onto it.
std::vector<std::uint32_t> Refiner::rim_runs_past_rim_points(const rim::RimOnB& rim) const {
  const rim::ExteriorMesh& m = mesh();
  std::map<std::uint32_t, std::vector<std::pair<double, std::uint32_t>>> on_edge;  // B edge -> (t, rim vertex)
  for (std::uint32_t v = 0; v < rim.on_b.size(); ++v)
    if (rim.on_b[v] && rim.at[v].kind == rim::Location::kEdge) on_edge[rim.at[v].id].push_back({rim.at[v].t, v});
  // Where a location lies along B edge e (its t, 0 or 1 at e's ends), or -1 when not on e.
  auto along = [&](const rim::Location& l, std::uint32_t e) {
    if (l.kind == rim::Location::kEdge) return l.id == e ? l.t : -1.0;
    if (l.kind == rim::Location::kVertex) return l.id == m.edges[e].x ? 0.0 : (l.id == m.edges[e].y ? 1.0 : -1.0);
    return -1.0;
  };
  std::vector<std::uint32_t> out;
  for (std::uint32_t k = 0; k < s_.edges.size(); ++k) {
    if (s_.edge_special[k] != kEdgeBoundary) continue;
    const glm::uvec2 ab = s_.edges[k];
    if (ab.x >= rim.on_b.size() || ab.y >= rim.on_b.size()) continue;
    // The B edge the segment may run along: one that an end lies inside (the other end on it too).
    const rim::Location &la = rim.at[ab.x], &lb = rim.at[ab.y];
    for (const rim::Location* end : {&la, &lb}) {
      if (end->kind != rim::Location::kEdge || (end == &lb && la.kind == rim::Location::kEdge && la.id == lb.id)) continue;
      const std::uint32_t e = end->id;
      const double ta = along(la, e), tb = along(lb, e);
      if (ta < 0.0 || tb < 0.0) continue;
      for (const auto& [t, v] : on_edge[e])
        if (v != ab.x && v != ab.y && t > std::min(ta, tb) && t < std::max(ta, tb)) out.insert(out.end(), {ab.x, ab.y, v});
    }
  }
  return out;
}

// The ends of rim edges that cross another rim edge inside a triangle of B, with the rim at
// `rim`: the pieces stage cuts the triangle along both and cannot ("two traced paths cross"). The
// same test as its cut: a proper crossing in the triangle's barycentric plane, exact (orient2d);
// edges sharing an end, and edges along a B edge (judged by rim_runs_past_rim_points), are not
// tested.
std::vector<std::uint32_t> Refiner::rim_segments_crossing(const rim::RimOnB& rim) const {
  const rim::ExteriorMesh& m = mesh();
  std::map<std::uint32_t, std::vector<glm::uvec2>> in_face;  // B triangle -> rim edges inside it
  for (std::uint32_t k = 0; k < s_.edges.size(); ++k) {
    if (s_.edge_special[k] != kEdgeBoundary) continue;
    const glm::uvec2 ab = s_.edges[k];
    if (ab.x >= rim.on_b.size() || ab.y >= rim.on_b.size() || !rim.on_b[ab.x] || !rim.on_b[ab.y]) continue;
    const std::uint32_t f = rim::common_face(m, rim.at[ab.x], rim.at[ab.y]);
    if (f == rim::kNone || (rim::location_sides(m, rim.at[ab.x], f) & rim::location_sides(m, rim.at[ab.y], f)) != 0u) continue;
    in_face[f].push_back(ab);
  }
  std::vector<std::uint32_t> out;
  for (const auto& entry : in_face) {
    const std::uint32_t f = entry.first;  // not a structured binding: clang before 16 cannot capture one in a lambda
    const std::vector<glm::uvec2>& edges = entry.second;
    if (edges.size() < 2) continue;
    auto uv = [&](std::uint32_t v) { return rim::location_uv(m, rim.at[v], f); };
    for (std::size_t i = 0; i < edges.size(); ++i)
      for (std::size_t j = i + 1; j < edges.size(); ++j) {
        const glm::uvec2 e = edges[i], g = edges[j];
        if (e.x == g.x || e.x == g.y || e.y == g.x || e.y == g.y) continue;
        const glm::dvec2 a = uv(e.x), b = uv(e.y), c = uv(g.x), d = uv(g.y);
        if (orient2d(a, b, c) * orient2d(a, b, d) < 0 && orient2d(c, d, a) * orient2d(c, d, b) < 0)
          out.insert(out.end(), {e.x, e.y, g.x, g.y});
      }
  }
  return out;
}

// hold_coincident_rim, then each moved vertex of a rim edge that runs along a B edge past another
// rim point, or that crosses another rim edge inside a B triangle (and those points or edges'
// ends, when they moved) back at x0, until nothing more is held.
std::size_t Refiner::hold_rim_degeneracies(const std::vector<glm::vec4>& x0, std::vector<glm::vec4>& x1) const {
  std::size_t held = 0;
  for (bool changed = true; changed;) {
    changed = false;
    held += hold_coincident_rim(s_, x0, x1);
    const rim::RimOnB rim = slid_rim(x1);  // once for both tests: it locates every moved rim vertex on B
    std::vector<std::uint32_t> bad = rim_runs_past_rim_points(rim);
    const std::vector<std::uint32_t> crossing = rim_segments_crossing(rim);
    bad.insert(bad.end(), crossing.begin(), crossing.end());
    for (const std::uint32_t v : bad)
      if (x1[v] != x0[v]) {
        x1[v] = x0[v];
        ++held;
        changed = true;
      }
  }
  return held;
}

// A rim vertex that slid into another triangle of B leaves its rim edges across B's edges: they
// are split where they cross them, as the rim was embedded at the start (embed_rim), before the
// iteration's splits, which split a rim edge only inside its triangle. The new vertices get what
// the refiner keeps per vertex (tree entry, last move, clearance, sample, velocity).
void Refiner::reembed_rim() {
  if (rim::find_unembedded_rim(s_, mesh(), rim_).empty()) return;
  embed_rim();
  inherit_moves();
  inherit_clearance(s_, tree_, clearance_);
  evaluate();
}

// Rim vertices made by splits since the last call lie on their rim edge's segment: their
// location is the point of that segment at the split's weight (the tree's), and their position
// that location's point.
void Refiner::locate_new_rim_vertices() {
  const std::size_t first = rim_.at.size();
  rim_.at.resize(s_.positions.size());
  rim_.on_b.resize(s_.positions.size(), 0);
  for (std::size_t v = first; v < s_.positions.size(); ++v) {
    if (!(s_.vertex_flags[v] & kVertexBoundary)) continue;
    const glm::uvec3 p = tree_.parents[v];
    const glm::vec3 w = tree_.weights[v];
    int ends[3], n = 0;
    for (int k = 0; k < 3; ++k)
      if (w[k] != 0.0f) ends[n++] = k;
    const int a = ends[0], b = n == 2 ? ends[1] : ends[0];
    if (n != 2 || !rim_.on_b[p[a]] || !rim_.on_b[p[b]])
      throw RunError("internal: rim vertex " + std::to_string(v) + " was split off a rim edge without a location on the exterior");
    const double t = double(w[b]) / (double(w[a]) + double(w[b]));
    rim_.at[v] = rim::split_location(mesh(), rim_, p[a], p[b], t);
    rim_.on_b[v] = 1;
    s_.positions[v] = glm::vec4(glm::vec3(rim_.at[v].point), 1.0f);
  }
}

// Splits, flips, then one flow step that moves the new vertices with the others. The splits may
// raise E a little (ψ at a sample is not the interpolation of its corners'), so the step must
// bring E to at most `e_before`, the energy the iteration started at; when no step does, the
// iteration's splits and flips are undone and S stays as it was. The step itself must lower E
// from where the splits left it, as any descent step. The splits are graded first (the
// longest-edge paths of Refiner::bisection), and some of them fall away from the samples, where
// the step gains nothing to pay for them; when it cannot, the iteration is made again with each
// split on its sample's own element (as the paper splits), and only when that is undone too does
// S stay as it was. After an iteration whose step did not move S (it pointed uphill for E, or
// every length was refused), the graded splits are not tried: a flow that could not lower E from
// where it was is not expected to win back what they add (on the wall's converged tail, all of
// them were undone).
IterationStats Refiner::iterate(std::uint32_t it, double e_before) {
  if (o_.rim_motion) reembed_rim();
  bool undone = false;
  IterationStats st = attempt(it, e_before, flow_moved_, undone);
  if (undone) {
    const double seconds = st.seconds;
    st = attempt(it, e_before, false, undone);
    st.seconds += seconds;
    st.attempts = 2;
  }
  return st;
}

IterationStats Refiner::attempt(std::uint32_t it, double e_before, bool graded, bool& undone) {
  IterationStats st;
  st.graded = graded;
  const auto t0 = Clock::now();
  const FractureSurface s_before = s_;
  const std::vector<glm::vec4> samples_before = samples_, velocity_before = velocity_;
  const std::vector<glm::vec3> moves_before = last_move_;
  std::size_t moved_by_paths = 0;
  st.splits = refine_step(it, graded, moved_by_paths);
  locate_new_rim_vertices();
  sample_new_vertices();
  st.phases.splits = seconds_since(t0);
  auto t1 = Clock::now();
  FlipOptions flip_options;
  flip_options.min_angle = o_.min_angle;
  flip_options.reject_face = [&](const glm::uvec4& f) {
    return face_crosses_exterior(f, s_.positions, mesh(), rim_, clearance_);
  };
  // A chord on B (a flat part of B holds both its ends): S's faces would lie on B there.
  flip_options.reject_diagonal = [&](std::uint32_t a, std::uint32_t b) {
    if (!rim_.on_b[a] || !rim_.on_b[b] || !(s_.vertex_flags[a] & kVertexBoundary) || !(s_.vertex_flags[b] & kVertexBoundary))
      return false;
    const glm::dvec3 mid = 0.5 * (rim_.at[a].point + rim_.at[b].point);
    return closest_point(mesh().bvh, mid).squared_distance <= std::pow(1e-6 * mesh().diagonal, 2);
  };
  st.flips = flip_slim_triangles(s_, samples_, b_, flip_options);
  st.phases.flips = seconds_since(t1);
  t1 = Clock::now();
  if (st.splits + st.flips > 0) evaluate();
  st.phases.evaluate = seconds_since(t1);
  t1 = Clock::now();
  const double e_now = energy();
  const bool moved = flow_step(e_now, std::min(e_before, e_now), st);
  flow_moved_ = moved;
  st.phases.flow = seconds_since(t1);
  if (!moved) st.energy = e_now;
  if (!moved && e_now > e_before) {
    s_ = s_before;
    samples_ = samples_before, velocity_ = velocity_before, last_move_ = moves_before;
    tree_.parents.resize(s_.positions.size()), tree_.weights.resize(s_.positions.size());
    clearance_.resize(s_.positions.size());
    rim_.at.resize(s_.positions.size()), rim_.on_b.resize(s_.positions.size());
    undone = moved_by_paths > 0;  // else the splits on the samples' own elements were these
    st.splits = st.flips = 0;
    st.energy = e_before;  // S is the one e_before was measured on
  }
  st.triangles = s_.faces.size();
  st.seconds = seconds_since(t0);
  return st;
}

// The scene's typical gradient: the root mean square of |∇ψ| over the field's nodes, and at least
// ψ's root mean square over the grid's diagonal, for a uniform field.
double typical_gradient(const FieldGrid4& field) {
  if (field.values.empty()) return 0.0;
  double g2 = 0.0, psi2 = 0.0;
  for (const glm::vec4& v : field.values)
    g2 += double(v.y) * v.y + double(v.z) * v.z + double(v.w) * v.w, psi2 += double(v.x) * v.x;
  const double n = double(field.values.size());
  const double diagonal = field.cell * glm::length(glm::dvec3(field.dims) - glm::dvec3(1.0));
  return std::max(std::sqrt(g2 / n), diagonal > 0.0 ? std::sqrt(psi2 / n) / diagonal : 0.0);
}

RefineResult Refiner::run(const RefineProgress& progress) {
  RefineResult result;
  tree_ = RefinementTree::identity(s_.positions.size());
  be_.set_field(field_);
  const double g = typical_gradient(field_);
  dt_ = g > 0.0 ? (o_.step > 0.0 ? o_.step : kDefaultStep) * o_.scale / g : 0.0;
  project_boundary_vertices(s_, b_);
  conform_boundary();
  tuck_inside(s_, tree_, b_, tuck_options());
  embed_rim();
  collar_rim(s_, tree_, mesh(), rim_);
  locate_new_rim_vertices();
  last_move_.assign(s_.positions.size(), glm::vec3(0.0f));
  evaluate();
  result.initial_energy = energy();
  double e = result.initial_energy;
  int calm = 0;  // iterations in a row that lowered E by less than the tolerance
  for (int it = 0; it < o_.max_iterations; ++it) {
    IterationStats st = iterate(std::uint32_t(it), e);
    const double decrease = e > 0.0 ? (e - st.energy) / e : 0.0;
    e = st.energy;
    result.iterations.push_back(st);
    if (progress) progress(st, it, o_.max_iterations);
    if (budget_reached_) {
      result.stop = RefineResult::Stop::kTriangleBudget;
      break;
    }
    // Converged when the surface stops lowering E (paper 4.4: "when the surface change in one
    // iteration is sufficiently small"), however many samples still ask for splits: past that
    // point they came from vertices the collisions or the step's backtracking held back, and
    // iterations that only split (3x the time on the wall) left E and the weak fraction as they
    // were. E falls in bursts, so one calm iteration is not enough. An iteration whose step did
    // not move S is calm too: its splits put their vertices on S's faces, so S keeps its shape,
    // and E falls only as its quadrature gets finer (the wall's tail: 0.08% to 0.01% an
    // iteration, with the step pointing uphill each time).
    calm = decrease < o_.tolerance || !flow_moved_ ? calm + 1 : 0;
    if (calm >= kCalmIterations) {
      result.stop = RefineResult::Stop::kConverged;
      break;
    }
  }
  // S was trimmed to B before the flow (rim/trim_to_exterior.hpp) and the flow's contact rule
  // keeps its faces from crossing B (hold_exterior_crossings): no tuck after the flow, whose
  // splits would put new vertices on B off the embedded rim.
  if (o_.rim_motion) reembed_rim();  // the last step's slides
  split_rim_chords(s_, tree_, b_, tuck_options(), kChordPasses);
  locate_new_rim_vertices();
  // Every edit is meant to keep S valid; a violation here is a bug, and it must not reach the
  // pieces or the output files silently. The derived arrays are the incremental rebuilds' (which
  // the unit tests compare with fresh ones): comparing them with a fresh rebuild here would cost
  // a full rebuild.
  if (std::string broken = validate_rebuilt(s_); !broken.empty())
    throw RunError("refinement produced an invalid fracture surface (an internal error; please report it): " + broken);
  if (std::string loose = rim::find_unembedded_rim(s_, mesh(), rim_); !loose.empty())
    throw RunError("refinement left the rim off the exterior (an internal error; please report it): " + loose);
  result.tree = std::move(tree_);
  result.rim = std::move(rim_);
  return result;
}

}  // namespace

RefineResult refine_surface(FractureSurface& s, const FieldGrid4& field, const ExteriorSurface& exterior,
                            ComputeBackend& backend, const RefineOptions& options, const RefineProgress& progress) {
  Refiner r(s, field, exterior, backend, options);
  return r.run(progress);
}

}  // namespace fracref
