#include "util/input_size.hpp"

#include <unistd.h>

#include <cstdio>

#include "util/error.hpp"

namespace fracref {

std::uint64_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 0;
  return std::uint64_t(pages) * std::uint64_t(page);
}

std::uint64_t max_input_file_bytes() {
  const std::uint64_t memory = physical_memory_bytes();
  if (memory == 0) return std::uint64_t(1) << 62;
  constexpr std::uint64_t kFloor = std::uint64_t(256) << 20;
  return memory / 4 > kFloor ? memory / 4 : kFloor;
}

std::string size_text(std::uint64_t bytes) {
  const char* units[] = {"KB", "MB", "GB", "TB", "PB"};
  if (bytes < 1000) return std::to_string(bytes) + (bytes == 1 ? " byte" : " bytes");
  double v = double(bytes) / 1000.0;
  int u = 0;
  while (v >= 1000.0 && u < 4) v /= 1000.0, ++u;
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %s", v, units[u]);
  return text;
}

void check_input_file_size(const std::filesystem::path& path, std::uint64_t size) {
  const std::uint64_t limit = max_input_file_bytes();
  if (size <= limit) return;
  throw InputError(path.string() + ": the file is " + size_text(size) + ", more than the " + size_text(limit) +
                   " fracref reads whole on this machine (" + size_text(physical_memory_bytes()) + " of memory)");
}

}  // namespace fracref
