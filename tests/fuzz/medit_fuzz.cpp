// libFuzzer harness: the MEDIT .mesh reader on arbitrary bytes.
#include "coarse/tet_readers.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  const auto path = fuzz::scratch_file("input.mesh", fuzz::as_text(data, size));
  return fuzz::run_reader([&] { read_medit(path); });
}
