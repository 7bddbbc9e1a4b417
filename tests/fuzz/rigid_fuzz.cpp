// libFuzzer harness: per-piece rigid transforms, for a model of two tets (two pieces) that share
// one vertex, so that the check of shared vertices runs too.
#include "coarse/animation.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  static const CoarseModel model = [] {
    CoarseModel m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {2, 0, 1}, {0, 2, 1}, {0, 0, 2}};
    m.tets = {{0, 1, 2, 3}, {3, 4, 5, 6}};
    m.tet_piece = {0, 1};
    m.piece_count = 2;
    m.piece_names = {"a", "b"};
    return m;
  }();
  const auto path = fuzz::scratch_file("transforms.txt", fuzz::as_text(data, size));
  return fuzz::run_reader([&] { load_rigid(path, 24.0, model); });
}
