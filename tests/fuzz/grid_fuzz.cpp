// libFuzzer harness: the strength grid file reader on arbitrary bytes.
#include "field/grid_file.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  const auto path = fuzz::scratch_file("input.grid", fuzz::as_text(data, size));
  return fuzz::run_reader([&] { read_strength_grid(path); });
}
