#include "util/atomic_output.hpp"

#include <set>

#include <unistd.h>

#include <fstream>
#include <system_error>

#include "util/error.hpp"

namespace fracref {
namespace fs = std::filesystem;

void write_file_atomic(const fs::path& path, const std::string& bytes) {
  fs::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw RunError(path.string() + ": cannot open for writing");
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw RunError(path.string() + ": write failed (disk full?)");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw RunError(path.string() + ": cannot rename temporary file into place: " + ec.message());
  }
}

void check_output_target(const fs::path& target) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(target, ec);
  if (ec || !fs::exists(st)) return;
  const std::string where = target.string() + ": ";
  if (!fs::is_directory(st))
    throw InputError(where + "exists and is not a folder; fracref replaces only its own output folders (choose another -o)");
  std::set<std::string> wrote;
  std::ifstream marker(target / kOutputMarker);
  for (std::string line; marker && std::getline(marker, line);) wrote.insert(line);
  const bool ours = bool(std::ifstream(target / kOutputMarker));
  for (const fs::directory_entry& e : fs::directory_iterator(target, ec)) {
    const std::string name = e.path().filename().string();
    if (name == kOutputMarker || wrote.count(name)) continue;
    throw InputError(where + (ours ? "holds '" + name + "', which fracref did not write"
                                   : "is a folder that fracref did not write (it holds '" + name + "')") +
                     "; fracref replaces only its own output folders and empty ones (choose another -o, or move the files)");
  }
  if (ec) throw InputError(where + "cannot be read: " + ec.message());
}

StagedDirectory::StagedDirectory(fs::path target) : target_(std::move(target)) {
  if (target_.filename().empty()) target_ = target_.parent_path();
  check_output_target(target_);
  staging_ = target_;
  staging_ += ".tmp-" + std::to_string(::getpid());
  std::error_code ec;
  fs::remove_all(staging_, ec);
  fs::create_directories(staging_, ec);
  if (ec) throw RunError(target_.string() + ": cannot create output folder: " + ec.message());
}

StagedDirectory::~StagedDirectory() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

void StagedDirectory::commit() {
  std::error_code ec;
  std::set<std::string> names;
  for (const fs::directory_entry& e : fs::directory_iterator(staging_, ec)) names.insert(e.path().filename().string());
  std::string list;
  for (const std::string& n : names) list += n + "\n";
  write_file_atomic(staging_ / kOutputMarker, list);
  // The previous output is moved aside first so the swap never leaves a mixed folder.
  fs::path old = target_;
  old += ".old-" + std::to_string(::getpid());
  bool had_old = fs::exists(target_, ec);
  if (had_old) {
    fs::rename(target_, old, ec);
    if (ec) throw RunError(target_.string() + ": cannot move the previous output aside: " + ec.message());
  }
  fs::rename(staging_, target_, ec);
  if (ec) {
    if (had_old) fs::rename(old, target_, ec);
    throw RunError(target_.string() + ": cannot move the new output into place: " + ec.message());
  }
  committed_ = true;
  if (had_old) fs::remove_all(old, ec);
}

}  // namespace fracref
