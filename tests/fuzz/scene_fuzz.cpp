// libFuzzer harness: a scene file (strict JSON, then the scene schema) on arbitrary bytes.
#include "fuzz/fuzz_support.hpp"
#include "scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  const auto path = fuzz::scratch_file("scene.json", fuzz::as_text(data, size));
  return fuzz::run_reader([&] { load_scene(path); });
}
