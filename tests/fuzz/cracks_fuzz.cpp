// libFuzzer harness: a cracks file, read and then applied to a fixed tet mesh (two cubes of one
// piece each, so that crack ids are range-checked and the cracks are cut).
#include "coarse/coarse_model.hpp"
#include "coarse/tet_readers.hpp"
#include "fuzz/fuzz_support.hpp"
#include "fuzz/fuzz_models.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  static const TetMesh mesh = fuzz::two_cubes();
  const auto path = fuzz::scratch_file("input.cracks", fuzz::as_text(data, size));
  return fuzz::run_reader([&] {
    const CrackList cracks = read_cracks(path);
    build_tet_model(mesh, &cracks);
  });
}
