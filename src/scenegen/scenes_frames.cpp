// The deforming scenes, animated by per-frame vertex positions with backward remeshing: the
// tree branch that bends and snaps, the twisted clay and the bouncing Jell-O.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "scenegen/scenes.hpp"
#include "util/error.hpp"

namespace fracref::scenegen_detail {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// Rotation of p about the line through `centre` along x.
glm::dvec3 rotate_about_x(const glm::dvec3& p, const glm::dvec3& centre, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), y = p.y - centre.y, z = p.z - centre.z;
  return {p.x, centre.y + y * c - z * s, centre.z + y * s + z * c};
}

// Per piece, the frame its copies of shared vertices appear in: `main` never leaves (it keeps
// the originals); the others, in the order given, leave at frames spread over [first, last].
std::vector<int> detach_frames(int pieces, int main, const std::vector<int>& order, int first, int last) {
  std::vector<int> frame(pieces, 1000);
  const int n = int(order.size());
  for (int i = 0; i < n; ++i)
    frame[order[i]] = n == 1 ? (first + last) / 2 : first + int(std::lround(double(last - first) * i / (n - 1)));
  frame[main] = 1000;
  return frame;
}

std::vector<int> others(int pieces, int main) {
  std::vector<int> out;
  for (int p = 0; p < pieces; ++p)
    if (p != main) out.push_back(p);
  return out;
}

// Bending of the branch into an arc of curvature kappa in the y-z plane, the plane z = 0 fixed,
// the ends going down (the top stretched: the tension side).
glm::dvec3 bend(const glm::dvec3& x, double kappa) {
  if (kappa < 1e-12) return x;
  const double r = 1.0 / kappa, rho = r + x.y, phi = x.z / r;
  return {x.x, -r + rho * std::cos(phi), rho * std::sin(phi)};
}

constexpr int kSnap = 20;              // the frame the branch snaps at
constexpr double kBranchLength = 4.0;  // the paper's 32 x 32 x 64 grid has cubic cells on a 2 x 2 x 4 box

// Bends until the snap, then the halves (groups 0 and 1: below and above the splintered cut)
// turn apart about the crack front; the uncut fibres below it (group -1, shared) hold them
// together, as in a green branch.
Motion branch_motion(double front, double open_angle) {
  const double kappa = 20.0 * kDegree / (0.5 * kBranchLength);  // the ends turn by 20 degrees
  return [=](const glm::dvec3& x, int group, int f) {
    const double k = kappa * (smoothstep01(f / double(kSnap)) + 0.3 * smoothstep01((f - kSnap) / 27.0));
    const glm::dvec3 p = bend(x, k);
    if (group < 0) return p;
    const double alpha = open_angle * smoothstep01((f - kSnap) / 24.0);
    return rotate_about_x(p, {0.0, front, 0.0}, group == 1 ? alpha : -alpha);
  };
}

// The clay held at y = -1 and twisted about y (growing angle, plastic: it never springs back),
// stretching and necking.
glm::dvec3 twist(const glm::dvec3& x, int f, double turns) {
  const double s = smoothstep01(f / 40.0), stretch = 1.0 + 0.25 * s, neck = 1.0 / std::sqrt(stretch);
  const double angle = turns * s * (x.y + 1.0) / 2.0, c = std::cos(angle), n = std::sin(angle);
  return {neck * (c * x.x + n * x.z), -1.0 + (x.y + 1.0) * stretch, neck * (-n * x.x + c * x.z)};
}

// A piece that tears off keeps its shape of that moment, spins and flies outward, falling.
Motion clay_motion(const PieceLayout& layout, const std::vector<int>& leave, double turns) {
  return [=, centroids = layout.centroids](const glm::dvec3& x, int group, int f) {
    if (group < 0 || f <= leave[group]) return twist(x, f, turns);
    const double t = (f - leave[group]) / kFps;
    const glm::dvec3 c = twist(centroids[group], leave[group], turns);
    glm::dvec3 out(c.x, 0.0, c.z);
    out = glm::length(out) > 1e-9 ? glm::normalize(out) : glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 p = c + rotation({0.0, 1.0, 0.0}, t) * (twist(x, leave[group], turns) - c);
    return p + 0.6 * t * out + glm::dvec3(0.0, -2.0 * t * t, 0.0);
  };
}

// The Jell-O hops on its base (z = 0) with squash and stretch (volume kept) and a decaying wobble.
glm::dvec3 bounce(const glm::dvec3& x, int f, double hop) {
  const double t = f / kFps, decay = std::exp(-t / 1.5), w = 2.0 * std::numbers::pi * 0.75;
  const double height = hop * decay * std::abs(std::cos(w * t)), s = 1.0 + 0.3 * decay * std::cos(2.0 * w * t);
  const double wobble = 0.08 * decay * std::sin(3.0 * w * t), across = 1.0 / std::sqrt(s);
  return {across * x.x + wobble * x.z, across * x.y, height + s * x.z};
}

// A piece that breaks off keeps wobbling while it slides outward and tips over.
Motion jello_motion(const PieceLayout& layout, const std::vector<int>& leave, double hop) {
  return [=, centroids = layout.centroids](const glm::dvec3& x, int group, int f) {
    const glm::dvec3 p = bounce(x, f, hop);
    if (group < 0 || f <= leave[group]) return p;
    const double t = (f - leave[group]) / kFps;
    const glm::dvec3 c = bounce(centroids[group], f, hop);
    glm::dvec3 out(c.x, c.y, 0.0);
    out = glm::length(out) > 1e-9 ? glm::normalize(out) : glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 axis = glm::normalize(glm::cross(glm::dvec3(0.0, 0.0, 1.0), out));
    return c + rotation(axis, std::min(0.7, 1.5 * t)) * (p - c) + 0.8 * t * out;
  };
}

// The labelled mesh as the last frame has it (a copy of every shared vertex per piece, appearing
// when the piece leaves) and the frames.
Json write_tearing(const SceneSetup& setup, PieceLayout& layout, const std::vector<int>& leave, const Motion& motion) {
  const Duplication dup = duplicate_vertices(layout.set, layout.labels, leave, {});
  write_medit(setup.folder / (setup.name + "_coarse.mesh"), layout.set, layout.labels);
  return write_frames_animation(setup, layout.set, dup, motion);
}

}  // namespace

Json make_branch(const SceneSetup& setup) {
  write_obj(setup.folder / "branch.obj", make_cylinder(1.0, kBranchLength, 32, 32),
            "tree branch: a capped cylinder, radius 1, length 4 along z");
  // Rings of 1, 8, 14 and 16 vertices: the cross-section has the paper's 60 triangles.
  constexpr int kLayers = 24;
  TetSet set = cylinder_tets(1.0, kBranchLength, {1, 8, 14, 16}, kLayers);
  Rng rng(setup.seed ^ 0xb2a7c4ull);
  const double front = -0.2 - 0.2 * rng.uniform();  // the crack covers y > front
  const double open_angle = (10.0 + 4.0 * rng.uniform()) * kDegree;
  const glm::dvec3 lo(-1.0, -1.0, -0.5 * kBranchLength), hi(1.0, 1.0, 0.5 * kBranchLength);
  SplinterOptions options;
  options.front = front;
  options.flip = rng.uniform() < 0.5;
  const SplinterCut crack = splinter_cut(set, kLayers, demo_strength(setup, lo, hi), options);
  const Duplication dup = duplicate_vertices(set, crack.side, {1000, kSnap}, crack.opens);
  write_medit(setup.folder / "branch_coarse.mesh", set, std::vector<int>(set.tets.size(), 0));
  write_faces(setup.folder / "branch_cracks.txt", crack.faces,
              "an incomplete, splintered cut across the middle of the branch: faces a b c (0-based vertex numbers)");
  const Json animation = write_frames_animation(setup, set, dup, branch_motion(front, open_angle));
  return scene_json(setup, animation, "branch_cracks.txt");
}

Json make_clay(const SceneSetup& setup) {
  const glm::dvec3 lo(-0.5, -1.0, -1.0), hi(0.5, 1.0, 1.0);
  constexpr double kRounding = 0.25;
  write_obj(setup.folder / "clay.obj", make_box(lo, hi, {20, 40, 40}, kRounding),
            "plastic clay: a rounded box 1 x 2 x 2 (edge radius 0.25)");
  // The box lattice mapped onto the rounded box as the exterior is: hull vertices are exterior vertices.
  TetSet set = box_lattice({lo, hi, {5, 10, 10}});
  for (glm::dvec3& p : set.positions) p = rounded_box_map(p, lo, hi, kRounding);
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    if (!(tet_volume(set, t) > 0.0)) throw RunError("scenegen: clay: a mapped lattice tet is flat or inverted");
  Rng rng(setup.seed ^ 0xc1a7ull);
  PieceLayout layout = piece_layout(std::move(set), {510, 6, 14, 8}, rng, [](const glm::dvec3&) { return 1.0; },
                                    demo_weakness(setup, lo, hi));
  // The bottom (y = -1) is held; the rest tears off late, top pieces first.
  const int main = piece_near(layout, {0.0, -1.0, 0.0});
  std::vector<int> order = others(layout.pieces, main);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return layout.centroids[a].y > layout.centroids[b].y; });
  const std::vector<int> leave = detach_frames(layout.pieces, main, order, 30, 44);
  const double turns = (0.9 + 0.2 * rng.uniform()) * std::numbers::pi;
  return scene_json(setup, write_tearing(setup, layout, leave, clay_motion(layout, leave, turns)));
}

Json make_jello(const SceneSetup& setup) {
  const glm::dvec3 lo(-1.0, -1.0, 0.0), hi(1.0, 1.0, 1.0);
  write_obj(setup.folder / "jello.obj", make_box(lo, hi, {40, 40, 20}), "Jell-O block 2 x 2 x 1, z up");
  Rng rng(setup.seed ^ 0x7e110ull);
  PieceLayout layout = piece_layout(box_lattice({lo, hi, {10, 10, 5}}), {488, 5, 12, 8}, rng,
                                    [](const glm::dvec3&) { return 1.0; }, demo_weakness(setup, lo, hi));
  // Gradual fracture: the piece at the centre of the base stays; the others come off one by one.
  const int main = piece_near(layout, {0.0, 0.0, 0.0});
  std::vector<int> order = others(layout.pieces, main);
  for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.next() % i]);
  const std::vector<int> leave = detach_frames(layout.pieces, main, order, 14, 44);
  const double hop = 0.3 + 0.2 * rng.uniform();
  return scene_json(setup, write_tearing(setup, layout, leave, jello_motion(layout, leave, hop)));
}

}  // namespace fracref::scenegen_detail
