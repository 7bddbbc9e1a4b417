#pragma once
// Internal to the check room.
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

/// The frames check (see check_output). \throw InputError when a frame file cannot be read.
void check_frames(const std::filesystem::path& out, const std::vector<PieceFile>& pieces, std::size_t frames,
                  CheckReport& report);

}  // namespace fracref::check_detail
