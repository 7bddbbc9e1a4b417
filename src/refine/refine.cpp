#include "refine/refine.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "flow/implicit_step.hpp"
#include "refine/collapses.hpp"
#include "refine/collisions.hpp"
#include "refine/containment.hpp"
#include "refine/exterior_contact.hpp"
#include "refine/flips.hpp"
#include "refine/motion_filters.hpp"
#include "refine/refiner.hpp"
#include "refine/relaxation.hpp"
#include "refine/rim_smoothing.hpp"
#include "refine/rim_collar.hpp"
#include "refine/step_guard.hpp"
#include "util/error.hpp"

namespace fracref {
namespace refine_detail {

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

// x0 + d, with the corners of the faces the contact rule flags at x0 kept (see flow_step), the
// boundary constraint applied, and with rim_motion the slid rim snapped.
std::vector<glm::vec4> Refiner::constrained_motion(const std::vector<glm::vec4>& x0, const std::vector<glm::dvec3>& d,
                                                   const std::vector<std::uint32_t>& flagged) {
  std::vector<glm::vec4> full = x0;
  for (std::size_t i = 0; i < x0.size(); ++i) full[i] = glm::vec4(glm::vec3(x0[i]) + glm::vec3(d[i]), 1.0f);
  // A face the contact rule flags at x0 already must not move (new_crossings): its corners stay
  // in the full step, and so in every shorter one. Held only where the full step leaves it
  // flagged, a face that the full step frees holds back every shorter step, which still flags it.
  for (const std::uint32_t f : flagged)
    for (int k = 0; k < 3; ++k) full[s_.faces[f][k]] = x0[s_.faces[f][k]];
  apply_boundary_constraint(s_, b_, x0, full);
  if (o_.rim_motion) {
    snap_slid_rim(full);
    hold_rim_degeneracies(x0, full);
  }
  return full;
}

// The step's motion from x0, the fold guard's holds made (flow_step then makes the collisions').
// With fold_solves > 1, the vertices the guard held stay where they are in a new solve, so that
// their neighbours take the step's quadratic's best motion around them instead of leaving a
// crease; until the guard holds nothing more or the solves run out.
std::vector<glm::vec4> Refiner::folding_held_motion(const std::vector<glm::vec4>& x0, const StepGuardOptions& guard,
                                                    IterationStats& st) {
  std::vector<glm::dmat3> filter = motion_filters(
      s_, b_, {.rim_motion = o_.rim_motion, .tangential = o_.tangential_motion, .threads = default_threads()});
  std::vector<glm::dvec3> d(x0.size());
  for (std::size_t i = 0; i < d.size() && i < last_move_.size(); ++i) d[i] = glm::dvec3(last_move_[i]);
  const std::vector<std::uint32_t> flagged = flagged_faces(x0, clearance_);
  for (int round = 0;; ++round) {
    st.solver_iterations += implicit_step(view(), samples_, velocity_, dt_, filter, d, {.threads = default_threads()}).iterations;
    std::vector<glm::dvec3> moved = d;
    add_tangential_relaxation(s_, s_.positions, moved, {.fraction = o_.relax, .threads = default_threads()});
    std::vector<glm::vec4> full = constrained_motion(x0, moved, flagged);
    const std::vector<glm::vec4> unguarded = full;
    hold_folding_motion(s_, x0, full, guard);
    if (full == unguarded || round + 1 >= o_.fold_solves) return full;
    for (std::size_t i = 0; i < full.size(); ++i)
      if (full[i] != unguarded[i]) filter[i] = glm::dmat3(0.0), d[i] = glm::dvec3(0.0);
  }
}

// Takes the step when it brings E to at most `ceiling` (backtracking as above) and sets st.energy
// to the new E; false when no step does, S then unchanged. `start` is E at the current positions.
// \pre samples_ and velocity_ are those of the current positions (run() evaluates after every
// edit; each evaluation is a kernel call, with a fixed cost on Vulkan).
bool Refiner::flow_step(double start, double ceiling, IterationStats& st) {
  const double e0 = ceiling;
  const std::vector<glm::vec4> x0 = s_.positions;
  const StepGuardOptions guard = step_guard_options();
  std::vector<glm::vec4> full = folding_held_motion(x0, guard, st);
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

// Hairpin tips collapsed before the splits; a collapsed tip keeps no face and stays where it is.
// The splits and flips read ψ at the vertices and the positions, which a collapse leaves as they
// were, so the velocities are evaluated once after all three (attempt).
std::size_t Refiner::collapse_hairpins() {
  CollapseOptions o;
  o.max_hairpin_degrees = o_.hairpin_collapse;
  o.reject_face = [&](const glm::uvec4& f) { return face_crosses_exterior(f, s_.positions, mesh(), rim_, clearance_); };
  const std::vector<std::uint32_t> tips = collapse_hairpin_tips(s_, o);
  for (const std::uint32_t v : tips) last_move_[v] = glm::vec3(0.0f);
  return tips.size();
}

IterationStats Refiner::attempt(std::uint32_t it, double e_before, bool graded, bool& undone) {
  IterationStats st;
  st.graded = graded;
  const auto t0 = Clock::now();
  const FractureSurface s_before = s_;
  const std::vector<glm::vec4> samples_before = samples_, velocity_before = velocity_;
  const std::vector<glm::vec3> moves_before = last_move_;
  std::size_t moved_by_paths = 0;
  st.collapses = collapse_hairpins();
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
  if (st.splits + st.flips + st.collapses > 0) evaluate();
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

namespace {

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

}  // namespace

RefineResult Refiner::run(const RefineProgress& progress) {
  RefineResult result;
  tree_ = RefinementTree::identity(s_.positions.size());
  be_.set_field(field_);
  const double g = typical_gradient(field_);
  dt_ = g > 0.0 ? (o_.step > 0.0 ? o_.step : kDefaultStep) * o_.scale / g : 0.0;
  project_boundary_vertices(s_, b_);
  smooth_rim(s_, b_, {.passes = o_.rim_smoothing});
  conform_boundary();
  tuck_inside(s_, tree_, b_, tuck_options());
  embed_rim();
  collar_rim(s_, tree_, mesh(), rim_);
  locate_new_rim_vertices();
  refuse_crossing_rim();
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

}  // namespace refine_detail

RefineResult refine_surface(FractureSurface& s, const FieldGrid4& field, const ExteriorSurface& exterior,
                            ComputeBackend& backend, const RefineOptions& options, const RefineProgress& progress) {
  refine_detail::Refiner r(s, field, exterior, backend, options);
  return r.run(progress);
}

}  // namespace fracref
