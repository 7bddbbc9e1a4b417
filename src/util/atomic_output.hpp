#pragma once
// Output that appears complete or not at all: write to a temporary name, then rename.
#include <filesystem>
#include <string>

namespace fracref {

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
/// \throw RunError "cannot write <file>: <cause>" (e.g. "No space left on device") when the file
///        cannot be written or renamed; <file> is user_path(path), the name the user asked for.
void write_file_atomic(const std::filesystem::path& path, const std::string& bytes);

/// `path` as the user knows it: every component "<name>.tmp-<this process's id>" (a staging
/// folder of StagedDirectory, or write_file_atomic's temporary file) becomes "<name>", so that
/// messages name the output asked for (-o OUT), e.g. "OUT/fracture_surface.ply", not where it
/// is staged ("OUT.tmp-4242/fracture_surface.ply"). Other paths are returned unchanged.
std::filesystem::path user_path(const std::filesystem::path& path);

/// `text` (a message) with every ".tmp-<this process's id>" not followed by a digit removed: the
/// user_path() of the paths quoted in messages fracref did not build itself (std::filesystem's).
std::string user_text(std::string text);

/// The file every output folder of fracref carries: the names of the entries fracref wrote there,
/// one a line. An existing folder is replaced only when it holds this file and nothing else.
inline constexpr const char* kOutputMarker = ".fracref-output";

/// Whether `target` may become an output folder: it does not exist, or it is an empty folder, or a
/// folder that fracref wrote (kOutputMarker) holding only what the marker names, or one without a
/// marker (written before it) holding report.json and only the names fracref writes.
/// \throw InputError naming `target` and what is in the way; nothing is touched.
void check_output_target(const std::filesystem::path& target);

/// Registers `folder` to be removed if the process gets SIGINT or SIGTERM (the handlers, installed
/// on the first call, remove every registered folder and exit with 128 + the signal). Returns a
/// slot for unregister_for_cleanup, or -1 when none is free (the folder is then not removed).
int register_for_cleanup(const std::filesystem::path& folder);
/// Forgets a folder registered by register_for_cleanup (-1: nothing).
void unregister_for_cleanup(int slot);

/// Removes the staging folders beside `target` ("<target>.tmp-<pid>", ".old-<pid>",
/// ".input-tmp-<pid>") whose process is gone: what a killed run could not clean up.
void remove_stale_staging(const std::filesystem::path& target);

/// A staging folder beside `target` ("<target>.tmp-<pid>") that becomes `target` on commit().
/// If commit() is never called the staging folder is removed, so a failed run leaves nothing
/// half-written: `target` is either the previous complete output or the new complete one.
class StagedDirectory {
 public:
  /// \throw InputError from check_output_target; RunError when the staging folder cannot be created.
  explicit StagedDirectory(std::filesystem::path target);
  ~StagedDirectory();
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  /// Where to write the files of the output.
  const std::filesystem::path& path() const { return staging_; }
  /// Writes the marker (the staging folder's entries) and replaces `target` by the staging
  /// folder. \throw RunError on failure.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path staging_;
  bool committed_ = false;
  int cleanup_slot_ = -1;
};

}  // namespace fracref
