#pragma once
// Output that appears complete or not at all: write to a temporary name, then rename.
#include <filesystem>
#include <string>

namespace fracref {

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
/// \throw RunError when the file cannot be written or renamed.
void write_file_atomic(const std::filesystem::path& path, const std::string& bytes);

/// A staging folder beside `target` ("<target>.tmp-<pid>") that becomes `target` on commit().
/// If commit() is never called the staging folder is removed, so a failed run leaves nothing
/// half-written: `target` is either the previous complete output or the new complete one.
class StagedDirectory {
 public:
  /// \throw RunError when the staging folder cannot be created.
  explicit StagedDirectory(std::filesystem::path target);
  ~StagedDirectory();
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  /// Where to write the files of the output.
  const std::filesystem::path& path() const { return staging_; }
  /// Replaces `target` by the staging folder. \throw RunError on failure.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace fracref
