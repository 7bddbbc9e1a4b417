// libFuzzer harness: an OBJ of open cut surfaces through the cuts input's coarse model build
// (coarse/cuts_model.hpp) inside a fixed exterior, the unit cube: clipping to B, the lattice's
// cracks, virtual fracture, the labels and S. A coarse lattice keeps each run short.
#include "coarse/cuts_model.hpp"
#include "fuzz/fuzz_support.hpp"
#include "io/mesh_io.hpp"

namespace {

fracref::MeshSoup unit_cube() {
  fracref::MeshSoup s;
  for (int k = 0; k < 8; ++k) s.positions.emplace_back(k & 1 ? 1.0 : 0.0, k & 2 ? 1.0 : 0.0, k & 4 ? 1.0 : 0.0);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2])});
    s.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[2]), std::uint32_t(q[3])});
  }
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  static const MeshSoup cube = unit_cube();
  const auto path = fuzz::scratch_file("cuts.obj", fuzz::as_text(data, size));
  return fuzz::run_reader([&] {
    const MeshSoup cuts = read_obj(path);
    CutsOptions o;
    o.auto_cells_first = 6.0;
    o.auto_cells_max = 12.0;
    build_cuts_model(cube, cuts, path.string(), o);
  });
}
