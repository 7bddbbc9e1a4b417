#include "util/atomic_output.hpp"

#include <set>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <atomic>
#include <cstring>

#include <fstream>
#include <system_error>

#include "util/error.hpp"

namespace fracref {
namespace fs = std::filesystem;

fs::path user_path(const fs::path& path) {
  const std::string suffix = ".tmp-" + std::to_string(::getpid());
  fs::path out;
  for (const fs::path& part : path) {
    const std::string name = part.string();
    const bool staged = name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
    out /= staged ? name.substr(0, name.size() - suffix.size()) : name;
  }
  return out;
}

std::string user_text(std::string text) {
  const std::string suffix = ".tmp-" + std::to_string(::getpid());
  for (std::size_t at = text.find(suffix); at != std::string::npos; at = text.find(suffix, at)) {
    const std::size_t end = at + suffix.size();
    if (end < text.size() && text[end] >= '0' && text[end] <= '9') at = end;
    else text.erase(at, suffix.size());
  }
  return text;
}

namespace {

// POSIX calls rather than a stream: errno then says why a write failed (ENOSPC, EDQUOT, EIO).
// Returns 0, or the errno of the first failure.
int write_all(const fs::path& file, const std::string& bytes) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) return errno;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : EIO;
      ::close(fd);
      return err;
    }
    done += std::size_t(n);
  }
  return ::close(fd) == 0 ? 0 : errno;
}

}  // namespace

void write_file_atomic(const fs::path& path, const std::string& bytes) {
  fs::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid());
  std::error_code ec;
  if (const int err = write_all(tmp, bytes)) {
    fs::remove(tmp, ec);
    throw RunError("cannot write " + user_path(path).string() + ": " + std::strerror(err));
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw RunError("cannot write " + user_path(path).string() + ": cannot rename the temporary file into place: " +
                   ec.message());
  }
}

namespace {

// Folders to remove if the process is interrupted (SIGINT, SIGTERM): fixed slots, as the handler
// may not allocate. A slot is claimed with a compare-exchange and released by clearing it.
constexpr std::size_t kSlots = 8, kPathBytes = 4096;
std::array<std::array<char, kPathBytes>, kSlots> g_paths{};
std::array<std::atomic<int>, kSlots> g_used{};

// Removes the registered folders with `rm -rf` in a child (_Fork, exec and waitpid are
// async-signal-safe; a recursive removal in the handler itself would not be), then exits with
// 128 + the signal, as a shell reports an interrupted command. Not fork(): glibc's takes malloc's
// locks, and a signal that lands inside malloc or free would wait on them for ever.
extern "C" void remove_staging_and_exit(int sig) {
  for (std::size_t i = 0; i < kSlots; ++i) {
    if (g_used[i].load() != 1) continue;
    const pid_t child = _Fork();
    if (child == 0) {
      char* const argv[] = {const_cast<char*>("rm"), const_cast<char*>("-rf"), const_cast<char*>("--"),
                            g_paths[i].data(), nullptr};
      execv("/bin/rm", argv);
      _exit(127);
    }
    if (child > 0) waitpid(child, nullptr, 0);
  }
  _exit(128 + sig);
}

void install_handlers() {
  static std::atomic<bool> installed{false};
  if (installed.exchange(true)) return;
  struct sigaction sa {};
  sa.sa_handler = remove_staging_and_exit;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

// Whether the folder beside `target` named "<target name><infix><pid>" belongs to a process that
// is gone (a stale staging folder of an interrupted or killed run).
bool stale(const fs::path& entry, const std::string& prefix) {
  const std::string name = entry.filename().string();
  if (name.rfind(prefix, 0) != 0 || name.size() == prefix.size()) return false;
  const std::string digits = name.substr(prefix.size());
  if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 9) return false;
  const pid_t pid = pid_t(std::stol(digits));
  return pid != ::getpid() && kill(pid, 0) != 0 && errno == ESRCH;
}

}  // namespace

int register_for_cleanup(const fs::path& folder) {
  install_handlers();
  const std::string p = folder.string();
  if (p.size() >= kPathBytes) return -1;
  for (std::size_t i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!g_used[i].compare_exchange_strong(expected, 2)) continue;  // 2: being written
    std::memcpy(g_paths[i].data(), p.c_str(), p.size() + 1);
    g_used[i].store(1);
    return int(i);
  }
  return -1;
}

void unregister_for_cleanup(int slot) {
  if (slot >= 0 && std::size_t(slot) < kSlots) g_used[std::size_t(slot)].store(0);
}

void remove_stale_staging(const fs::path& target) {
  std::error_code ec;
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const std::string base = target.filename().string();
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    for (const char* infix : {".tmp-", ".old-", ".input-tmp-"})
      if (stale(e.path(), base + infix)) fs::remove_all(e.path(), ec);
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
  bool ours = bool(std::ifstream(target / kOutputMarker));
  // An output folder of a fracref from before the marker: report.json and only the names fracref
  // writes (so that rerunning a command into its old output keeps working).
  if (!ours && fs::exists(target / "report.json", ec)) {
    wrote = {"report.json", "preview.png", "preview_surface.png", "preview_frames.png", "coarse_surface.ply",
             "fracture_surface.ply", "exterior.ply", "pieces", "frames", "animation.glb", "input"};
    ours = true;
  }
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
  remove_stale_staging(target_);
  staging_ = target_;
  staging_ += ".tmp-" + std::to_string(::getpid());
  std::error_code ec;
  fs::remove_all(staging_, ec);
  cleanup_slot_ = register_for_cleanup(staging_);
  fs::create_directories(staging_, ec);
  if (ec) {
    unregister_for_cleanup(cleanup_slot_);
    throw RunError(target_.string() + ": cannot create output folder: " + ec.message());
  }
}

StagedDirectory::~StagedDirectory() {
  unregister_for_cleanup(cleanup_slot_);
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
  unregister_for_cleanup(cleanup_slot_);
  if (had_old) fs::remove_all(old, ec);
}

}  // namespace fracref
