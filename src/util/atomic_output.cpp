#include "util/atomic_output.hpp"

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

StagedDirectory::StagedDirectory(fs::path target) : target_(std::move(target)) {
  if (target_.filename().empty()) target_ = target_.parent_path();
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
