#pragma once
// Internal to the check room.
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "check/check_output.hpp"
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

/// The frames check (see check_output). \throw InputError when a frame file cannot be read.
void check_frames(const std::filesystem::path& out, const std::vector<PieceFile>& pieces, std::size_t frames,
                  CheckReport& report);

/// The glb check of animation.glb (see check_output); failures are recorded, never thrown.
void check_glb(const std::filesystem::path& out, const std::vector<PieceFile>& pieces, std::size_t frames,
               CheckReport& report);

}  // namespace fracref::check_detail
