// Messages about outputs name the path the user asked for (-o OUT), not the staging folder the
// files are written to first; a write that fails says why (e.g. the disk is full).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fs = std::filesystem;
using namespace fracref;

namespace {

const std::string kPid = std::to_string(::getpid());

std::string run_error(const fs::path& path, const std::string& bytes) {
  try {
    write_file_atomic(path, bytes);
  } catch (const RunError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(UserPath, MapsThisProcesssStagingFolderBackToTheOutput) {
  EXPECT_EQ(user_path("/data/out.tmp-" + kPid + "/fracture_surface.ply"), fs::path("/data/out/fracture_surface.ply"));
  EXPECT_EQ(user_path("out.tmp-" + kPid + "/pieces/piece_0.obj"), fs::path("out/pieces/piece_0.obj"));
  EXPECT_EQ(user_path("out.tmp-" + kPid), fs::path("out"));
  // Another process's folder, a longer number, or a user's own name stay as they are.
  EXPECT_EQ(user_path("/data/out.tmp-" + kPid + "7/a.ply"), fs::path("/data/out.tmp-" + kPid + "7/a.ply"));
  EXPECT_EQ(user_path("/data/notes.tmp/a.ply"), fs::path("/data/notes.tmp/a.ply"));
  EXPECT_EQ(user_path("/data/out/a.ply"), fs::path("/data/out/a.ply"));
}

TEST(UserText, RemovesTheStagingSuffixFromMessages) {
  EXPECT_EQ(user_text("filesystem error: cannot create directories: No space left on device [/d/out.tmp-" + kPid +
                      "/pieces]"),
            "filesystem error: cannot create directories: No space left on device [/d/out/pieces]");
  EXPECT_EQ(user_text("out.tmp-" + kPid + "1 stays"), "out.tmp-" + kPid + "1 stays");
  EXPECT_EQ(user_text("no staging here"), "no staging here");
}

// /dev/full fails every write with ENOSPC: the temporary file write_file_atomic writes through
// is made a link to it, as a full disk would fail the write, and the message must name the
// output the user asked for and the cause.
TEST(WriteFileAtomic, DiskFullNamesTheUsersOutputAndTheCause) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const fs::path root = fs::temp_directory_path() / ("fracref_atomic_" + kPid);
  const fs::path staging = root / ("out.tmp-" + kPid);
  fs::remove_all(root);
  fs::create_directories(staging);
  const fs::path file = staging / "fracture_surface.ply";
  fs::create_symlink("/dev/full", file.string() + ".tmp-" + kPid);
  EXPECT_EQ(run_error(file, std::string(100000, 'x')),
            "cannot write " + (root / "out" / "fracture_surface.ply").string() + ": No space left on device");
  EXPECT_FALSE(fs::exists(file));
  EXPECT_FALSE(fs::is_symlink(file.string() + ".tmp-" + kPid));  // the temporary name is cleaned up
  fs::remove_all(root);
}

TEST(WriteFileAtomic, MissingFolderNamesTheFileAndTheCause) {
  const fs::path file = fs::temp_directory_path() / ("fracref_atomic_none_" + kPid) / "a.txt";
  EXPECT_EQ(run_error(file, "x"), "cannot write " + file.string() + ": No such file or directory");
}

TEST(WriteFileAtomic, WritesTheBytes) {
  const fs::path file = fs::temp_directory_path() / ("fracref_atomic_ok_" + kPid + ".txt");
  write_file_atomic(file, std::string("a\0b", 3));
  std::ifstream in(file, std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), std::string("a\0b", 3));
  fs::remove(file);
}
