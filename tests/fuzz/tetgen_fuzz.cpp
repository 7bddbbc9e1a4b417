// libFuzzer harness: the TetGen reader. The input is the .node file, a line "@@ele", then the
// .ele file (without that line the .ele file is empty).
#include "coarse/tet_readers.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  const auto [node, ele] = fuzz::split_at(fuzz::as_text(data, size), "\n@@ele\n");
  fuzz::scratch_file("input.node", node);
  const auto path = fuzz::scratch_file("input.ele", ele);
  return fuzz::run_reader([&] { read_tetgen(path); });
}
