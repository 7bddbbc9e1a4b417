// libFuzzer harness: the strict OFF reader on arbitrary bytes.
#include "fuzz/fuzz_support.hpp"
#include "io/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  const auto path = fuzz::scratch_file("input.off", fuzz::as_text(data, size));
  return fuzz::run_reader([&] { read_off(path); });
}
