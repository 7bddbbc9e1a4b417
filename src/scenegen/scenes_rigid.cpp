// The rigid-body scenes: the marble bunny falling apart and the brick wall hit by a wrecking ball.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include "field/procedural.hpp"
#include "io/mesh_io.hpp"
#include "scenegen/scenes.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref::scenegen_detail {
namespace {

// The bunny as given: it must be a closed, outward mesh to be an exterior.
TriMesh read_bunny(const std::filesystem::path& path) {
  if (path.empty())
    throw InputError("demo scene 'bunny': no bunny OBJ given (DemoOptions::bunny_obj; set-up puts the npm bunny@1.0.1 "
                     "as build/data/bunny.obj)");
  if (!std::filesystem::is_regular_file(path))
    throw InputError(path.string() + ": no such file (the Stanford bunny OBJ of the bunny demo scene)");
  const MeshSoup soup = read_mesh(path);
  TriMesh mesh{soup.positions, soup.triangles};
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) ++directed[{t[e], t[(e + 1) % 3]}];
  for (const auto& [edge, n] : directed) {
    const auto back = directed.find({edge.second, edge.first});
    if (n != 1 || back == directed.end() || back->second != 1)
      throw InputError(path.string() + ": not a closed mesh: edge " + std::to_string(edge.first + 1) + "-" +
                       std::to_string(edge.second + 1) + " is not shared by exactly two faces in opposite directions");
  }
  if (mesh_volume(mesh) <= 0.0) throw InputError(path.string() + ": the mesh is inside out (negative volume)");
  return mesh;
}

void copy_file_bytes(const std::filesystem::path& from, const std::filesystem::path& to) {
  std::ifstream in(from, std::ios::binary);
  if (!in) throw InputError(from.string() + ": cannot be read");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  write_file_atomic(to, bytes.str());
}

// Every piece gets its own vertices (pieces that move apart cannot share one).
void give_pieces_own_vertices(PieceLayout& layout) {
  duplicate_vertices(layout.set, layout.labels, std::vector<int>(layout.pieces, 0), {});
}

// A piece thrown at `start` frames with `velocity`, spinning at `spin` rad/s about `axis`, under gravity -y.
RigidTransform thrown(const glm::dvec3& centroid, int frame, int start, const glm::dvec3& velocity,
                      const glm::dvec3& axis, double spin, double gravity) {
  const double t = std::max(0, frame - start) / kFps;
  RigidTransform x;
  x.rotation = rotation(axis, spin * t);
  const glm::dvec3 moved = velocity * t + glm::dvec3(0.0, -0.5 * gravity * t * t, 0.0);
  x.translation = centroid + moved - x.rotation * centroid;
  return x;
}

// The exterior's bounding box.
std::pair<glm::dvec3, glm::dvec3> bounds(const TriMesh& exterior) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const glm::dvec3& p : exterior.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return {lo, hi};
}

// A lattice of cubes of a tenth of the exterior's longest side, with one cube to spare on
// every side.
LatticeSpec padded_lattice(const TriMesh& exterior) {
  LatticeSpec lattice;
  std::tie(lattice.lo, lattice.hi) = bounds(exterior);
  const glm::dvec3 extent = lattice.hi - lattice.lo;
  const double h = std::max({extent.x, extent.y, extent.z}) / 10.0;
  lattice.cells = glm::ivec3(glm::ceil(extent / h - 1e-9)) + 2;
  const glm::dvec3 middle = 0.5 * (lattice.lo + lattice.hi), half = 0.5 * h * glm::dvec3(lattice.cells);
  lattice.lo = middle - half, lattice.hi = middle + half;
  return lattice;
}

// The bunny's pieces burst apart a little and fall, each spinning slowly.
std::vector<std::vector<RigidTransform>> falling_apart(const PieceLayout& layout, Rng& rng) {
  glm::dvec3 centre(0.0);
  double volume = 0.0;
  for (int p = 0; p < layout.pieces; ++p) centre += layout.volumes[p] * layout.centroids[p], volume += layout.volumes[p];
  centre /= volume;
  std::vector<std::vector<RigidTransform>> frames(kFrames, std::vector<RigidTransform>(layout.pieces));
  for (int p = 0; p < layout.pieces; ++p) {
    glm::dvec3 out = layout.centroids[p] - centre;
    out = glm::length(out) > 1e-9 ? glm::normalize(out) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 velocity = 2.5 * out + glm::dvec3(0.0, 1.5, 0.0) + 0.5 * rng.direction();
    const glm::dvec3 axis = rng.direction();
    const double spin = rng.uniform(0.8, 2.0);
    for (int f = 0; f < kFrames; ++f) frames[f][p] = thrown(layout.centroids[p], f, 4, velocity, axis, spin, 12.0);
  }
  return frames;
}

constexpr double kReach = 0.8;                   // of the wrecking ball, around its impact
const glm::dvec3 kImpact(0.3, 0.45, 0.1);        // on the wall's front face; the ball moves along -z

double reach(const glm::dvec3& p) { return glm::length(glm::dvec2(p.x - kImpact.x, p.y - kImpact.y)); }

// Pieces within the ball's reach fly off (faster near the impact); the pieces above the hole lose
// their support and fall a little later; the rest of the wall stands.
std::vector<std::vector<RigidTransform>> knocked_out(const PieceLayout& layout, Rng& rng) {
  std::vector<std::vector<RigidTransform>> frames(kFrames, std::vector<RigidTransform>(layout.pieces));
  for (int p = 0; p < layout.pieces; ++p) {
    const glm::dvec3 c = layout.centroids[p];
    glm::dvec3 side(c.x - kImpact.x, c.y - kImpact.y, 0.0);
    side = glm::length(side) > 1e-9 ? glm::normalize(side) : glm::dvec3(0.0);
    const glm::dvec3 axis = rng.direction();
    if (reach(c) < kReach) {
      const double speed = 1.0 + 4.0 * (1.0 - reach(c) / kReach);
      const glm::dvec3 velocity = speed * glm::normalize(glm::dvec3(0.0, 0.0, -1.0) + 0.5 * side);
      for (int f = 0; f < kFrames; ++f) frames[f][p] = thrown(c, f, 6, velocity, axis, 1.5 * speed, 9.81);
    } else if (c.y > kImpact.y && std::abs(c.x - kImpact.x) < kReach) {
      const double spin = rng.uniform(0.2, 0.8);
      for (int f = 0; f < kFrames; ++f) frames[f][p] = thrown(c, f, 12, glm::dvec3(0.0), axis, spin, 9.81);
    }
  }
  return frames;
}

}  // namespace

Json make_bunny(const SceneSetup& setup, const std::filesystem::path& bunny_obj) {
  const TriMesh exterior = read_bunny(bunny_obj);
  copy_file_bytes(bunny_obj, setup.folder / "bunny.obj");
  Rng rng(setup.seed ^ 0xb0a4a11ce5ull);
  const auto [lo, hi] = bounds(exterior);
  PieceLayout layout = piece_layout(stuffed_tets(exterior, padded_lattice(exterior), 0.3), {256, 5, 10, 8}, rng,
                                    [](const glm::dvec3&) { return 1.0; }, demo_weakness(setup, lo, hi));
  give_pieces_own_vertices(layout);
  write_medit(setup.folder / "bunny_coarse.mesh", layout.set, layout.labels);
  return scene_json(setup, write_rigid_animation(setup, falling_apart(layout, rng)));
}

namespace {

// The demo's brick field (its default parameters) on the wall [lo, hi]: brick size, mortar and
// pitch in scene units, lengths relative to lo as the material measures them.
struct WallBricks {
  glm::dvec3 size;
  double mortar;
  glm::dvec2 pitch;
  double bond_offset;
};

WallBricks wall_bricks(const glm::dvec3& lo, const glm::dvec3& hi) {
  const BrickParams b;
  const double diagonal = glm::length(hi - lo);
  const glm::dvec3 size = b.brick_size * diagonal;
  const double mortar = b.mortar * diagonal;
  return {size, mortar, glm::dvec2(size.x + mortar, size.y + mortar), b.bond_offset};
}

// A box_lattice cell's tets (LayoutGoal::cell_tets).
constexpr int kCellTets = 6;

// The wall's coarse mesh as a masonry model meshes a wall, unit by unit: a box lattice whose
// planes lie in the middle of the mortar joints of the demo's brick field, the bed joints across
// y and, across x, a plane at every half brick, where the head joints of one course or the next
// lie (courses are offset by half a brick). Planes closer than 0.4 of a pitch to the wall's ends
// are left out, so no cell is a sliver.
TetSet brick_lattice(const glm::dvec3& lo, const glm::dvec3& hi, const WallBricks& w) {
  const auto planes = [](double first, double step, double length) {
    std::vector<double> p{0.0};
    for (double c = first; c < length - 0.4 * step; c += step)
      if (c > 0.4 * step) p.push_back(c);
    p.push_back(length);
    return p;
  };
  const std::vector<double> xs = planes(w.size.x + 0.5 * w.mortar - w.pitch.x, 0.5 * w.pitch.x, hi.x - lo.x);
  const std::vector<double> ys = planes(w.size.y + 0.5 * w.mortar, w.pitch.y, hi.y - lo.y);
  TetSet set = box_lattice({lo, hi, {int(xs.size()) - 1, int(ys.size()) - 1, 2}});
  for (glm::dvec3& p : set.positions) {
    const int i = int(std::lround((p.x - lo.x) / (hi.x - lo.x) * double(xs.size() - 1)));
    const int j = int(std::lround((p.y - lo.y) / (hi.y - lo.y) * double(ys.size() - 1)));
    p.x = lo.x + xs[i], p.y = lo.y + ys[j];
  }
  return set;
}

// The brick each cell of brick_lattice lies in (its course and its place in the course,
// numbered), from the centroid of the cell's tets: each unit is the cells of one brick.
std::vector<int> brick_units(const TetSet& set, const glm::dvec3& lo, const WallBricks& w) {
  std::vector<int> units(set.tets.size() / kCellTets);
  for (std::size_t c = 0; c < units.size(); ++c) {
    glm::dvec3 m(0.0);
    for (std::uint32_t t = std::uint32_t(c * kCellTets); t < (c + 1) * kCellTets; ++t)
      m += tet_centroid(set, t) / double(kCellTets);
    const double course = std::floor((m.y - lo.y) / w.pitch.y);
    const double brick = std::floor((m.x - lo.x - course * w.bond_offset * w.pitch.x) / w.pitch.x);
    units[c] = int(course) * 1000 + int(brick) + 500;
  }
  return units;
}

}  // namespace

Json make_wall(const SceneSetup& setup) {
  const glm::dvec3 lo(-1.5, 0.0, -0.1), hi(1.5, 1.0, 0.1);
  write_obj(setup.folder / "wall.obj", make_box(lo, hi, {60, 20, 4}), "brick wall 3 x 1 x 0.2, y up");
  Rng rng(setup.seed ^ 0x3a11b41150ull);
  // Small pieces near the impact, large ones far from it, laid out by the material on a lattice
  // of half bricks whose bricks stay whole: the cracks run in the joints, as a masonry model's do.
  const WallBricks bricks = wall_bricks(lo, hi);
  TetSet lattice = brick_lattice(lo, hi, bricks);
  std::vector<int> units = brick_units(lattice, lo, bricks);
  PieceLayout layout = piece_layout(std::move(lattice), {204, 8, 20, 6, kCellTets, std::move(units)}, rng,
                                    [](const glm::dvec3& p) { return 0.3 + 0.7 * std::min(1.0, reach(p) / 1.2); },
                                    demo_weakness(setup, lo, hi));
  give_pieces_own_vertices(layout);
  write_medit(setup.folder / "wall_coarse.mesh", layout.set, layout.labels);
  return scene_json(setup, write_rigid_animation(setup, knocked_out(layout, rng)));
}

}  // namespace fracref::scenegen_detail
