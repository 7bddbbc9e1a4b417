// libFuzzer harness: an OBJ of open cut surfaces through the cuts input's coarse model build
// (coarse/cuts_model.hpp) inside a fixed exterior, the unit cube: clipping to B, the lattice's
// cracks, virtual fracture, the labels and S. A coarse lattice keeps each run short.
#include "coarse/cuts_model.hpp"
#include "fuzz/fuzz_models.hpp"
#include "fuzz/fuzz_support.hpp"
#include "io/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  static const MeshSoup cube = fuzz::box(glm::dvec3(0.0), glm::dvec3(1.0));
  const auto path = fuzz::scratch_file("cuts.obj", fuzz::as_text(data, size));
  return fuzz::run_reader([&] {
    const MeshSoup cuts = read_obj(path);
    CutsOptions o;
    o.auto_cells_first = 6.0;
    o.auto_cells_max = 12.0;
    build_cuts_model(cube, cuts, path.string(), o);
  });
}
