#pragma once
// Internal to the check room.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "check/check_output.hpp"
#include <glm/glm.hpp>

#include "io/mesh_soup.hpp"

namespace fracref::check_detail {

/// One piece as read back from its file.
struct PieceFile {
  std::string name;  ///< relative to the output folder, e.g. "pieces/piece_001.ply"
  bool present = false;
  MeshSoup mesh;
  std::vector<std::uint8_t> inside;  ///< per triangle
};

/// Sets `report.checks`' entry `name` (appending it) and adds the failures, if any.
void record(CheckReport& report, const std::string& name, const std::vector<std::string>& failures,
            const std::string& detail);
void record_skipped(CheckReport& report, const std::string& name, const std::string& why);

/// The piece's triangles in the order its OBJ (and every frame) lists them: outside, then
/// inside; only the outside (0) or inside (1) ones when `only_group` is 0 or 1.
std::vector<std::array<std::uint32_t, 3>> obj_order(const PieceFile& f, int only_group = -1);

/// Frame t of frames/ as every piece's vertices in piece order. \throw InputError when it cannot be read.
using FrameReader = std::function<std::vector<glm::dvec3>(std::size_t)>;

/// The frames check (see check_output) of frames/positions.bin and topology.obj when
/// positions.bin is there, else of frames/frame_NNNN.obj. Returns a reader of the frames when
/// they passed, else an empty one. \throw InputError when a frame file cannot be read.
FrameReader check_frames(const std::filesystem::path& out, const std::vector<PieceFile>& pieces, std::size_t frames,
                         CheckReport& report);

/// The glb check of animation.glb (see check_output), then, with a `frame` reader, the
/// glb_frames check; failures are recorded, never thrown.
void check_glb(const std::filesystem::path& out, const std::vector<PieceFile>& pieces, std::size_t frames,
               const FrameReader& frame, CheckReport& report);

}  // namespace fracref::check_detail
