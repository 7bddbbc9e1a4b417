// libFuzzer harness: per-frame positions. The input is one frame file, optionally followed by a
// line "@@parents" and a parent map (backward remeshing), read for a model of 8 vertices.
#include "coarse/animation.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  static const CoarseModel model = [] {
    CoarseModel m;
    m.vertices.assign(8, glm::dvec3(0.0));
    return m;
  }();
  const auto [frame, parents] = fuzz::split_at(fuzz::as_text(data, size), "\n@@parents\n");
  fuzz::scratch_file("frame_0.txt", frame);
  const bool remesh = !parents.empty();
  const auto map = remesh ? fuzz::scratch_file("parents.txt", parents) : std::filesystem::path();
  return fuzz::run_reader([&] { load_frames(fuzz::scratch_dir() / "frame_{}.txt", 0, 1, 24.0, map, model); });
}
