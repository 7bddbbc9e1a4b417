#pragma once
// Input files are read whole: their size is checked first, so that a huge file is refused by a
// message naming it instead of ending in std::bad_alloc after minutes.
#include <cstdint>
#include <filesystem>
#include <string>

namespace fracref {

/// The machine's physical memory in bytes (0 when the system does not say).
std::uint64_t physical_memory_bytes();

/// The largest input file fracref reads whole: a quarter of the physical memory (the bytes and
/// what is parsed from them must fit side by side), at least 256 MiB; 2^62 when memory is unknown.
std::uint64_t max_input_file_bytes();

/// "1.5 GB", "12 KB", "7 bytes": a size for messages (decimal units).
std::string size_text(std::uint64_t bytes);

/// Checks, before anything is read, that `path` (a regular file of `size` bytes) may be read whole.
/// \throw InputError "<file>: the file is <size>, more than the <limit> fracref reads whole on this
///        machine (<memory> of memory)" when size > max_input_file_bytes().
void check_input_file_size(const std::filesystem::path& path, std::uint64_t size);

}  // namespace fracref
