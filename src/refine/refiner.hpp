#pragma once
// The working class of refine_surface (refine.hpp), private to the refine module: its members are
// defined in refine.cpp (the loop, the flow step), refine_splits.cpp (the samples and the splits)
// and refine_rim.cpp (the rim on B: conforming, embedding, sliding, and the contact with B).
#include <chrono>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "field/field_sampler.hpp"
#include "refine/containment.hpp"
#include "refine/refine.hpp"
#include "refine/samples.hpp"
#include "refine/step_guard.hpp"
#include "rim/rim_on_b.hpp"

namespace fracref::refine_detail {

// The flow step (flow/implicit_step.hpp) is semi-implicit: its length is set by the scene, not
// by the smallest triangle. dt = step · scale / g, g the root mean square of |∇ψ| over the field's
// nodes: at the field's typical gradient a vertex is driven `step` of the diagonal per iteration.
// If the energy rises the step is halved (at most kBacktracks times) and, failing that, not taken.
inline constexpr double kDefaultStep = 0.004;
inline constexpr int kBacktracks = 6;
inline constexpr int kInsertBacktracks = 10;
// Converged after this many iterations in a row that lower E by less than the tolerance.
inline constexpr int kCalmIterations = 2;
inline constexpr double kConformTolerance = 2e-4;  // of the diagonal
inline constexpr int kConformPasses = 8;
// Passes of split_rim_chords after the loop (a pass splits each face at most once).
inline constexpr int kChordPasses = 4;
// Barycentric weights below this are zeroed where a rim vertex slides on B (Refiner::slid_rim).
inline constexpr double kSlideSnap = 1e-3;

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

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
  void refuse_crossing_rim() const;
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
  std::vector<glm::vec4> folding_held_motion(const std::vector<glm::vec4>& x0, const StepGuardOptions& guard,
                                             IterationStats& st);
  std::vector<glm::vec4> constrained_motion(const std::vector<glm::vec4>& x0, const std::vector<glm::dvec3>& d,
                                            const std::vector<std::uint32_t>& flagged);
  std::size_t collapse_hairpins();
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

}  // namespace fracref::refine_detail
