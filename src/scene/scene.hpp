#pragma once
// A scene file: one refinement job, read strictly from JSON (schema: scenes/SCHEMA.md).
// Lengths are in scene units (the exterior mesh's units) unless a field says otherwise.
// Every path is absolute and lexically normal: relative paths in the file are resolved
// against the scene file's folder. Referenced files are not opened here (the loaders do).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace fracref {

enum class FractureKind { tets, pieces, cuts };
enum class AnimationKind { none, frames, rigid };
enum class FieldType { marble, wood, branch, brick, inclusions, perlin, fbm, constant, grid };

/// The low-resolution fracture. Exactly one of `mesh` / `files` is set (`files` only for pieces).
struct FractureSpec {
  FractureKind kind = FractureKind::tets;
  std::filesystem::path mesh;                ///< tets: MEDIT .mesh or TetGen .ele; pieces: OBJ with o/g per piece; cuts: OBJ of open cuts
  std::vector<std::filesystem::path> files;  ///< pieces: one mesh file per piece
  std::filesystem::path cracks;              ///< tets only, optional (empty = none): faces cracked inside one piece
  bool virtual_fracture = true;              ///< extend incomplete cuts until every cut separates
  double cells_per_diagonal = 0.0;           ///< cuts and pieces (when fitted): the tet lattice's cell is the exterior's diagonal / this; 0 = automatic
  double tolerance = 0.005;                  ///< pieces only: the widest gap closed between pieces, a fraction of the exterior's diagonal
};

/// How the low-resolution fracture moves. kind none: static pieces, no frames.
struct AnimationSpec {
  AnimationKind kind = AnimationKind::none;
  std::filesystem::path frames;      ///< frames: pattern with one {} or {:0N} field (see frame_path())
  std::int64_t first = 0;            ///< frames: number of the first frame
  std::int64_t count = 0;            ///< frames: number of frames (>= 1 when kind is frames)
  std::filesystem::path parent_map;  ///< frames, optional (empty = none): backward-remeshing parent map
  std::filesystem::path transforms;  ///< rigid: per-piece per-frame rigid transforms
  double fps = 24.0;                 ///< playback rate written to animated outputs
};

/// The strength field ζ and the grid it is sampled on.
struct FieldSettings {
  FieldType type = FieldType::marble;
  glm::uvec3 resolution{0, 0, 0};  ///< grid nodes per axis, each in [2, 1024]; {0,0,0} for a grid field given without one
  double padding = 0.05;           ///< fraction of the exterior's bbox diagonal added around it
  std::uint64_t seed = 1;          ///< seed of procedural fields
  std::filesystem::path file;      ///< grid only: the strength grid file
  nlohmann::json params = nlohmann::json::object();  ///< type-specific, validated by the field room ("field.params")
};

/// ψ = strength·ζ + distance·d + offset.
struct WeightsSpec {
  double strength = 1.0;
  double distance = 4.0;
  double offset = 0.05;
};

struct PyramidSpec {
  int levels = 5;      ///< Gaussian pyramid levels, in [1, 8]
  double sigma = 1.0;  ///< Gaussian blur between levels, in grid cells
};

/// The refine loop. Lengths given as fractions of the exterior's bbox diagonal.
struct RefineSpec {
  double tau = 0.002;           ///< split threshold
  double delta = 0.004;         ///< minimum sample-to-vertex distance
  double step = 0.0;            ///< flow step length at the typical gradient; 0 = the refiner's default
  double tolerance = 5e-4;      ///< converged when E falls by less than this fraction in an iteration
  int max_iterations = 200;     ///< in [0, 100000]: a safety limit
  std::int64_t max_triangles = 2000000;  ///< in [1, 50000000]: a safety limit
  std::uint64_t seed = 1;       ///< seed of the random samples
  double min_angle = 20.0;      ///< degrees, in [0, 60): flip edges of triangles with a smaller angle
  bool collisions = true;       ///< continuous collision handling
  bool rim_motion = false;      ///< the rim (S's boundary on B) slides on B with the flow
  bool tangential_motion = true;  ///< a vertex inside a sheet moves along S too (else along its normal)
  double relax = 0.0;           ///< in [0, 1]: tangential relaxation of the sheets' vertices per step (0: off)
  /// Passes of rim smoothing on B before the flow (0: off); absent: kLatticeRimSmoothing where S
  /// is the label boundary of a tet lattice (cuts, and pieces fitted on one), whose zig-zag on B
  /// is the lattice's and not the input's, else 0.
  std::optional<int> rim_smoothing;
  int fold_solves = 2;          ///< in [1, 8]: solves per flow step, held vertices fixed after the first
  double hairpin_collapse = 45.0;  ///< degrees in [0, 90]: junction hairpins sharper than this lose their tip; 0 = off
};

/// refine.rim_smoothing's default where S comes from a tet lattice of B.
constexpr int kLatticeRimSmoothing = 2;

struct OutputSpec {
  bool ply = true;
  bool obj = true;
  bool glb = true;
  bool frames = false;    ///< frames/ when the scene is animated (scenes/OUTPUTS.md)
  /// frames/ as one topology plus per-frame positions ("bin") or one OBJ per frame ("obj").
  std::string frames_format = "bin";
  bool preview = true;    ///< preview.png
  int preview_frames = 0; ///< animated preview frames, in [0, 1000]
};

struct Scene {
  std::filesystem::path file;      ///< the scene file, absolute and lexically normal
  std::string name;                ///< default: the scene file's stem
  std::filesystem::path exterior;  ///< closed triangle mesh (obj/off/ply)
  FractureSpec fracture;
  AnimationSpec animation;
  FieldSettings field;
  WeightsSpec weights;
  PyramidSpec pyramid;
  RefineSpec refine;
  OutputSpec output;
};

/// Reads and validates a scene file.
/// \throw InputError naming the file and the key (by dotted path, e.g. 'refine.tau') or the
///        line:column of a JSON syntax error, for: a missing or unreadable file, bad JSON, a
///        duplicate, unknown or missing key, a wrong type, a non-integer where an integer is
///        expected, a value out of range, or an inconsistent combination of keys.
Scene load_scene(const std::filesystem::path& file);

/// Validates an already parsed scene. `file` names it in messages and anchors relative paths.
/// \throw InputError as load_scene() (except the file and syntax errors).
Scene parse_scene(const nlohmann::json& json, const std::filesystem::path& file);

/// The path of frame number `frame`: the {} or {:0N} field of `pattern` replaced by the number
/// (zero-padded to N digits for {:0N}).
/// \pre `pattern` was validated by parse_scene (one field).
std::filesystem::path frame_path(const std::filesystem::path& pattern, std::int64_t frame);

const char* to_string(FractureKind kind);
const char* to_string(AnimationKind kind);
const char* to_string(FieldType type);

}  // namespace fracref
