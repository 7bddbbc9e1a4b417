#pragma once
// `fracref check OUT`: re-reads an output folder written by fracref with the strict readers and
// re-verifies what docs/DESIGN.md "What the outputs must satisfy" promises. The folder layout and
// every check are documented in scenes/OUTPUTS.md.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pieces/pieces.hpp"

namespace fracref {

enum class CheckStatus { kPassed, kFailed, kSkipped };

/// One named check and its outcome.
struct CheckResult {
  std::string name;    ///< "report", "piece_files", "piece_meshes", "partition", "shared_vertices", "frames", "glb"
  CheckStatus status = CheckStatus::kSkipped;
  std::string detail;  ///< what was checked ("3 pieces, 12480 triangles"), or why it was skipped
};

struct CheckOptions {
  /// The partition check: random points, seed, volume tolerance (default 0.1%), self-intersection cap.
  PieceCheckOptions pieces;
};

struct CheckReport {
  std::vector<CheckResult> checks;  ///< in the order above
  /// One line per failure, naming the file (and piece or frame) and why, e.g.
  /// "pieces/piece_001.ply: not closed (2 edges with one face, e.g. 4-9)".
  std::vector<std::string> failures;
  std::size_t pieces = 0;  ///< piece count from report.json
  std::size_t frames = 0;  ///< frame count from report.json
  bool ok() const { return failures.empty(); }
  /// 0 when every check passed or was skipped, 1 when one failed (2 is the InputError case).
  int exit_code() const { return ok() ? 0 : 1; }
};

/// Checks the output folder `out`:
///  - report: report.json is a JSON object with non-negative integers `pieces` and `frames`;
///  - piece_files: pieces/piece_NNN.ply (or .obj when no PLY was written) for NNN in
///    [0, pieces), no other piece_* mesh, triangle counts equal report.json's `piece_meshes`;
///  - piece_meshes: each piece closed, edge-manifold, consistently oriented, outward (positive
///    volume), free of self-intersections (exact), not empty;
///  - partition: against exterior.ply, the volumes sum to the exterior's within
///    options.pieces.volume_tolerance and every random point inside it lies in exactly one piece;
///  - shared_vertices: every vertex of a fracture (inside) face of a piece has the same position,
///    bit for bit, as a vertex of a fracture face of another piece;
///  - frames: frames/frame_NNNN.obj for NNNN in [0, frames) and no other, each with groups
///    piece_000 .. in order, each group on its own consecutive vertices, as many as the piece
///    file's, and the piece file's triangles (in its OBJ order: outside faces, then inside);
///  - glb: animation.glb is a GLB 2 file (magic, version, length equal to the file size, a JSON
///    and a BIN chunk, each a multiple of 4 bytes, nothing after them) whose JSON parses (no
///    repeated key) with asset.version "2.0"; one buffer, the BIN chunk; every buffer view
///    inside it and every accessor inside its view; one node per piece, named piece_NNN, whose
///    mesh's primitives have float VEC3 POSITION accessors with min and max and as many
///    vertices as the piece file, and uint32 triangles equal to the piece file's outside (or,
///    for material "inside", inside) faces; as many morph targets as kept frames after the
///    first (report.json's frames, thinned by animations[0].extras.frame_step as
///    gltf_writer.hpp describes), each with min and max; one animation with one weights channel
///    per node, its sampler keyed at every kept frame (input with min and max).
/// The piece checks are skipped when report.json has no `piece_meshes` and there is no pieces/
/// folder (a run stopped before the pieces stage); the frames check when there is no frames/
/// folder (a run without the animate stage); the glb check when there is no animation.glb. The
/// glb check stops at the first problem it finds and records it as its failure (never an
/// InputError).
/// \throw InputError when `out` is not a fracref output or a file in it cannot be read: no
///        folder, no or malformed report.json, a missing key, or a mesh the strict readers reject
///        (message naming the file, and line or byte, and the cause); also a piece PLY without
///        the `inside` face property.
CheckReport check_output(const std::filesystem::path& out, const CheckOptions& options = {});

/// The report as JSON: {"ok", "pieces", "frames", "checks": [{"name", "status", "detail"}],
/// "failures": [...]}, status one of "passed", "failed", "skipped".
nlohmann::ordered_json check_report_json(const CheckReport& report);

/// "passed", "failed" or "skipped".
const char* check_status_name(CheckStatus status);

}  // namespace fracref
