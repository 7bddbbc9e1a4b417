#include "io/mesh_io.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include "io/mesh_writers.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

enum class MeshFormat { Obj, Off, Ply };

MeshFormat format_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".ply") return MeshFormat::Ply;
  std::string shown = ext.empty() ? "no extension" : "unsupported extension '" + path.extension().string() + "'";
  throw InputError(path.string() + ": " + shown + " (mesh files must be .obj, .off or .ply)");
}

}  // namespace

MeshSoup read_mesh(const std::filesystem::path& path) {
  switch (format_of(path)) {
    case MeshFormat::Obj: return read_obj(path);
    case MeshFormat::Off: return read_off(path);
    case MeshFormat::Ply: return read_ply(path);
  }
  return {};
}

void write_mesh(const std::filesystem::path& path, const MeshSoup& soup, const MeshWriteOptions& options) {
  const MeshFormat format = format_of(path);
  const std::string file = path.string();
  io_detail::check_soup_for_writing(soup, file);
  std::string bytes;
  switch (format) {
    case MeshFormat::Obj: bytes = io_detail::obj_bytes(soup, file); break;
    case MeshFormat::Off: bytes = io_detail::off_bytes(soup); break;
    case MeshFormat::Ply: bytes = io_detail::ply_bytes(soup, options.ply_binary, file); break;
  }
  write_file_atomic(path, bytes);
}

}  // namespace fracref
