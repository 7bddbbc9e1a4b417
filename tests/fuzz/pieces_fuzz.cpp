// libFuzzer harness: a pieces OBJ (one `o`/`g` group per piece) through the coarse model build:
// the exact path, and the fit on a tet lattice (coarse/pieces_fit.hpp) when the pieces do not
// conform. The exterior is the box around the pieces' vertices (or the unit cube when that box is
// flat or not finite), so the fit labels a real lattice; a coarse lattice keeps each run short.
#include <cmath>

#include "coarse/pieces_fit.hpp"
#include "fuzz/fuzz_models.hpp"
#include "fuzz/fuzz_support.hpp"

namespace {

fracref::MeshSoup box_around(const std::vector<fracref::PieceInput>& pieces) {
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : pieces)
    for (const glm::dvec3& x : p.positions) lo = glm::min(lo, x), hi = glm::max(hi, x);
  const glm::dvec3 size = hi - lo;
  if (!(size.x > 0 && size.y > 0 && size.z > 0 && std::isfinite(size.x + size.y + size.z))) lo = glm::dvec3(0), hi = glm::dvec3(1);
  return fracref::fuzz::box(lo, hi);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fracref;
  const auto path = fuzz::scratch_file("pieces.obj", fuzz::as_text(data, size));
  return fuzz::run_reader([&] {
    const std::vector<PieceInput> pieces = read_pieces(path);
    FitOptions o;
    o.cells_per_diagonal = 6;
    o.max_cells_per_diagonal = 12;
    o.tolerance = 0.1;
    build_pieces_or_fit(box_around(pieces), "box.obj", pieces, {}, o);
  });
}
