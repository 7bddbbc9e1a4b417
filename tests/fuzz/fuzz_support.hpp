#pragma once
// What every libFuzzer harness of fracref's readers shares: the fuzzer's bytes become a file
// (the readers take paths), and the project's own InputError is a normal outcome. Any other
// exception is reported and aborts, so libFuzzer records it as a finding, as it does crashes,
// sanitizer reports and hangs.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>

#include "util/error.hpp"

namespace fracref::fuzz {

/// A scratch folder of this process, created on first use (under $TMPDIR or /tmp).
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = std::filesystem::temp_directory_path() / ("fracref_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

/// Writes `bytes` to scratch_dir()/name and returns the path.
/// \pre name is a plain file name.
inline std::filesystem::path scratch_file(const std::string& name, std::string_view bytes) {
  const std::filesystem::path path = scratch_dir() / name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0) std::abort();
  return path;
}

/// The bytes as text.
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// `text` split at the first `separator` line ("\n@@name\n"): (before, after); after is empty
/// when the separator is absent.
inline std::pair<std::string_view, std::string_view> split_at(std::string_view text, std::string_view separator) {
  const std::size_t at = text.find(separator);
  if (at == std::string_view::npos) return {text, {}};
  return {text.substr(0, at), text.substr(at + separator.size())};
}

/// Runs `read`; an InputError is the expected answer to bad input, anything else is a finding.
template <class F>
int run_reader(F&& read) {
  try {
    read();
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fracref fuzz: unexpected exception: %s\n", e.what());
    std::abort();
  }
  return 0;
}

}  // namespace fracref::fuzz
