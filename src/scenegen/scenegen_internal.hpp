#pragma once
// Building blocks of the demo scenes. Not part of the public API.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "geom/bvh.hpp"

#include "coarse/tet_lattice.hpp"

namespace fracref::scenegen_detail {

/// splitmix64: a small seeded generator (no std distributions, so the output is the same on
/// every standard library).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1).
  double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// A unit vector, uniform on the sphere.
  glm::dvec3 direction();

 private:
  std::uint64_t state_;
};

/// A triangle mesh (the exterior B).
struct TriMesh {
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// ------------------------------------------------------------------------------------------------
// Exteriors (closed, outward), exteriors.cpp

/// A capped cylinder about the z axis, z in [-length/2, length/2]: `segments` around, `rings`
/// bands along z, caps fanned around a centre vertex.
TriMesh make_cylinder(double radius, double length, int segments, int rings);

/// Maps the box [lo, hi] onto the rounded box of edge radius `radius` (the box shrunk by
/// `radius`, grown back by a ball): a point's offset d from the shrunk box is rescaled to the
/// Euclidean length its largest coordinate has, so the box's surface lands on the rounded
/// surface, flat parts stay, and the inside follows continuously (a homeomorphism).
/// \pre 2 radius < every extent of the box.
glm::dvec3 rounded_box_map(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi, double radius);

/// The surface of the box [lo, hi] with `cells` grid cells per axis on its faces, each cell two
/// triangles. With `rounding` > 0 every point is mapped by rounded_box_map.
TriMesh make_box(const glm::dvec3& lo, const glm::dvec3& hi, const glm::ivec3& cells, double rounding = 0.0);

/// Signed volume (positive for a closed outward mesh).
double mesh_volume(const TriMesh& mesh);

// ------------------------------------------------------------------------------------------------
// Coarse tet meshes: lattice.cpp (tet sets, the Kuhn lattice), cylinder.cpp, stuffing.cpp

using TetSet = fracref::TetSet;  // coarse/tet_lattice.hpp
using LatticeSpec = fracref::LatticeSpec;

/// Faces of a TetSet: interior faces (two tets) and hull faces (one tet, wound outward).
struct TetFaces {
  std::vector<glm::uvec3> interior;       ///< wound outward from interior_tets[i].x
  std::vector<glm::uvec2> interior_tets;  ///< the two tets (x < y)
  std::vector<glm::uvec3> hull;           ///< wound outward
  std::vector<std::uint32_t> hull_tet;
};

/// \throw RunError when a face is shared by more than two tets.
TetFaces tet_faces(const TetSet& set);

/// Where a closed triangle surface is not a 2-manifold: edges used by more than two faces, as
/// (a, b) with a < b, then vertices whose faces form more than one fan, as (v, v).
std::vector<std::pair<std::uint32_t, std::uint32_t>> surface_defects(const std::vector<glm::uvec3>& faces);

/// A capped cylinder about z, z in [-length/2, length/2], filled with tets: a disc of rings of
/// `ring_counts` vertices (the first 1: the centre) at evenly spaced radii, extruded over
/// `layers` layers, each prism split into 3 tets by vertex order (conforming). The outer ring's
/// vertices are those of make_cylinder(radius, length, 2 * ring_counts.back(), ...) at even
/// positions, bit for bit, so the hull is inscribed in that exterior and touches it at them.
/// Vertices are numbered layer by layer (z ascending), disc order within a layer.
TetSet cylinder_tets(double radius, double length, const std::vector<int>& ring_counts, int layers);

/// coarse/tet_lattice.hpp's stuffed_tets on a TriMesh, and its hull must be a 2-manifold.
/// \throw RunError when no tet is inside, or the hull is not a 2-manifold.
TetSet stuffed_tets(const TriMesh& exterior, const LatticeSpec& spec, double warp);

/// Per vertex, the tets that use it (CSR).
struct VertexTets {
  std::vector<std::uint32_t> offsets, tets;
};
VertexTets vertex_tets(const TetSet& set);

glm::dvec3 tet_centroid(const TetSet& set, std::uint32_t t);

// ------------------------------------------------------------------------------------------------
// Pieces, labels.cpp

/// `count` well-spread sites among the tet centroids (Mitchell's best candidate of 12), the
/// distance to the nearest earlier site divided by `spacing(site)` (a local size; 1 = uniform).
/// Sites come out in the order chosen, so the first k of count are the k-site layout.
std::vector<glm::dvec3> spread_sites(const TetSet& set, int count, Rng& rng,
                                     const std::function<double(const glm::dvec3&)>& spacing);

/// Per tet, the nearest site's index.
std::vector<int> voronoi_labels(const TetSet& set, const std::vector<glm::dvec3>& sites);

/// How costly it is, per unit length, for a coarse crack's pieces to grow through a point.
using CrackCost = std::function<double(const glm::dvec3&)>;

/// The strength ζ in [0, 1] of a material at a point.
using Strength = std::function<double(const glm::dvec3&)>;

/// ζ of the demo material `field_type` (default parameters, `seed`) on the object box [lo, hi]:
/// the material the refiner reads from the same scene.
/// \throw InputError as validate_field_spec().
Strength material_strength(const std::string& field_type, std::uint64_t seed, const glm::dvec3& lo,
                           const glm::dvec3& hi);

/// Added to ζ in weakness_cost, so that a point of ζ = 0 costs finitely much.
inline constexpr double kCostFloor = 0.05;

/// 1 / (ζ + kCostFloor): weak material is cheap to crack through.
CrackCost weakness_cost(Strength zeta);

/// Per interior face, the cost of the segment joining its two tets' centroids: its length times
/// the largest `cost` at eight points along it (the weakest material between the two tets, which
/// a thin weak layer such as the wall's brick-mortar interface would be lost in a mean).
std::vector<double> crossing_costs(const TetSet& set, const TetFaces& faces, const CrackCost& cost);

/// Per tet, the site nearest through the tets' face graph, with `costs` (crossing_costs) on its
/// edges: a geodesic Voronoi labelling whose cells meet where crossing is dear (weak material),
/// as a coarse simulation of that material would crack. Each site starts at its nearest tet.
std::vector<int> geodesic_labels(const TetSet& set, const TetFaces& faces, const std::vector<glm::dvec3>& sites,
                                 const std::vector<double>& costs);

/// A crack across a cylinder_tets set, and the two sides it separates.
struct SplinterCut {
  std::vector<int> side;              ///< per tet: 0 below the cut, 1 above
  std::vector<int> height;            ///< per column (disc triangle): the cut's layer, from the middle one
  std::vector<glm::uvec3> faces;      ///< the cracked faces: faces between the sides whose centroid has y > front
  std::vector<std::uint8_t> opens;    ///< per vertex: every face between the sides at it is cracked
};

struct SplinterOptions {
  double front = 0.0;           ///< the crack covers y > front; the bend opens it about the line y = front, z = 0
  double radius = 1.0;          ///< the cylinder's
  double reach = 10.0;          ///< layers a fibre of ζ = 1 at the far side (y = radius) pulls out of the other half
  bool flip = false;            ///< splinters at x > 0 stay with the upper half (else the lower), those at x < 0 the other
  double min_wall_slope = 0.0;  ///< the least y part of a step wall's normal towards its taller side (0: walls may slide)
};

/// The tree branch's coarse crack, as a coarse simulation of a green branch snapping in
/// bending would leave it: on the tension side (away from the hinge, the line y = front, z = 0)
/// fibres pull out of the other half as splinters. Each column of tets (a disc triangle) wants
/// to break reach × tension × ζ layers from the middle (tension: 0 where the column reaches
/// down to the hinge, 1 at the far side; ζ from `strength`, at the middle), towards the upper
/// half on one side of x = 0 and the lower half on the other (`flip`). The columns then grow from a
/// flat cut towards what they want, farthest from the hinge first, each as far as it may
/// beside its neighbours, so that the opening (the sides turning apart about the hinge line)
/// pulls every step wall apart or slides it, never closes it (correct by construction):
/// columns breaking above and below the middle never touch, and across each wall the column
/// that breaks farther from the middle lies on the far side from the hinge (the wall's normal
/// towards it has a y part of min_wall_slope or more). Then columns are brought back towards
/// the middle wherever either side's tets would pinch along a vertical edge (more than one run
/// of a side about it at some layer), and wherever that breaks a wall rule, until both hold, so
/// both sides are 2-manifold solids. Deterministic.
/// \pre set = cylinder_tets(options.radius, ..., layers) with layers even.
/// \throw RunError when set is not such a set.
SplinterCut splinter_cut(const TetSet& set, int layers, const Strength& strength, const SplinterOptions& options);

/// Makes the labels a clean piece layout, renumbered 0, 1, ... by lowest tet: every label's tets
/// face-connected (parts get labels of their own; parts of fewer than `min_tets` tets join the
/// neighbour they share most faces with); every piece a 2-manifold solid; and at most one cut
/// face at each hull edge (the loader could not tell which pieces lie between two). At such a
/// defect (an edge or vertex) the tets around it take the label most of them have, after ten
/// rounds the lowest label among them (so that alternating fixes end).
/// \throw RunError when the layout does not settle in 1000 rounds.
void tidy_labels(const TetSet& set, const TetFaces& faces, std::vector<int>& labels, std::size_t min_tets);

/// Interior faces whose two tets have different labels.
std::size_t cut_face_count(const TetFaces& faces, const std::vector<int>& labels);

/// Voronoi labels of the first k sites for k in [k_lo, k_hi] (geodesic_labels when `costs` is
/// not empty), with whole_cells when cell_tets > 1 and whole_units when `units` is not empty,
/// tidied; the layout whose cut face count is closest to `target` (ties to the smaller k).
/// \pre units empty or one per cell of cell_tets tets.
std::vector<int> best_layout(const TetSet& set, const TetFaces& faces, const std::vector<glm::dvec3>& sites, int k_lo,
                             int k_hi, std::size_t target, std::size_t min_tets, const std::vector<double>& costs = {},
                             int cell_tets = 1, const std::vector<int>& units = {});

/// Gives each run of `cell_tets` consecutive tets (a box_lattice cell: 6 tets) the label most of
/// them have (ties to the lowest), so that cuts run only on the cells' faces.
void whole_cells(std::vector<int>& labels, int cell_tets);

/// Gives every tet of the cells (runs of cell_tets tets) of one unit the label most of them have
/// (ties to the lowest), so that no cut runs inside a unit. \pre units.size() * cell_tets <= labels.size().
void whole_units(std::vector<int>& labels, int cell_tets, const std::vector<int>& units);

// ------------------------------------------------------------------------------------------------
// Duplicated vertices (a simulator's last frame), duplicate.cpp

/// The result of splitting vertices between groups of tets.
struct Duplication {
  std::vector<std::uint32_t> parent;  ///< per vertex of the new set: its original (itself for originals)
  std::vector<int> group;             ///< per vertex: the group whose tets use it (originals: the owner)
  std::vector<int> split_frame;       ///< per vertex: first frame it exists in (0 for originals)
  std::size_t original_count = 0;     ///< vertices before the copies
};

/// Gives every group of tets its own copy of each vertex it shares with another group, when
/// `may_split[v]` (empty = all). The owner of a shared vertex keeps the original: the group
/// using it with the largest split frame (ties to the lowest group). Copies are appended,
/// ordered by (split frame of their group, original, group), so that a frame's vertices are a
/// prefix. Tets of group g are rewritten to use g's copies.
/// \param group_split_frame per group, the frame its copies appear in.
Duplication duplicate_vertices(TetSet& set, const std::vector<int>& tet_group, const std::vector<int>& group_split_frame,
                               const std::vector<std::uint8_t>& may_split);

// ------------------------------------------------------------------------------------------------
// Files, writers.cpp

/// Shortest decimal text that reads back as the same double (locale-free).
void append_number(std::string& out, double value);

/// The files of scenes/INPUTS.md, written with write_file_atomic (\throw RunError on failure).
void write_obj(const std::filesystem::path& path, const TriMesh& mesh, const std::string& comment);
/// MEDIT .mesh (1-based indices); labels[t] is tet t's reference (its piece label).
void write_medit(const std::filesystem::path& path, const TetSet& set, const std::vector<int>& labels);
/// A cracks file: `a b c` per face, 0-based.
void write_faces(const std::filesystem::path& path, const std::vector<glm::uvec3>& faces, const std::string& comment);
/// One text frame: `x y z` per vertex.
void write_frame(const std::filesystem::path& path, const std::vector<glm::dvec3>& points);
/// `v parent` for every vertex whose parent is not itself.
void write_parent_map(const std::filesystem::path& path, const std::vector<std::uint32_t>& parent);
/// A piece's rigid transform x' = R x + t.
struct RigidTransform {
  glm::dmat3 rotation{1.0};
  glm::dvec3 translation{0.0};
};
/// `frame piece r00 r01 r02 t0 r10 ...` for frames[frame][piece].
void write_rigid(const std::filesystem::path& path, const std::vector<std::vector<RigidTransform>>& frames);

/// Rotation by `angle` radians about the unit `axis`.
glm::dmat3 rotation(const glm::dvec3& axis, double angle);
/// 3x^2 - 2x^3 of x clamped to [0, 1].
double smoothstep01(double x);

}  // namespace fracref::scenegen_detail
