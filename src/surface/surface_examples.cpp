// Hand-built example surfaces on integer lattice points.
#include "surface/surface_examples.hpp"

#include <algorithm>
#include <array>
#include <map>

#include "util/error.hpp"

namespace fracref {
namespace {

// Collects quads on lattice points, sharing a vertex wherever two quads share a point.
class LatticeBuilder {
 public:
  std::uint32_t vertex(glm::ivec3 p) {
    auto [it, inserted] = ids_.try_emplace({p.x, p.y, p.z}, std::uint32_t(positions_.size()));
    if (inserted) positions_.emplace_back(glm::vec3(p), 1.0f);
    return it->second;
  }
  // Corners in order: the normal is (c1 - c0) x (c3 - c0) and points into `front`.
  void quad(glm::ivec3 c0, glm::ivec3 c1, glm::ivec3 c2, glm::ivec3 c3, int front, int back) {
    const std::uint32_t a = vertex(c0), b = vertex(c1), c = vertex(c2), d = vertex(c3);
    faces_.emplace_back(a, b, c, 0);
    faces_.emplace_back(a, c, d, 0);
    pieces_.emplace_back(front, back);
    pieces_.emplace_back(front, back);
  }
  FractureSurface build(int piece_count) {
    return make_fracture_surface(std::move(positions_), std::move(faces_), std::move(pieces_), piece_count);
  }

 private:
  std::map<std::array<int, 3>, std::uint32_t> ids_;
  std::vector<glm::vec4> positions_;
  std::vector<glm::uvec4> faces_;
  std::vector<glm::ivec2> pieces_;
};

// The quads of the plane z = 0 for x in [x0, x0 + 1], y in [0, cells], normal +z.
void horizontal_strip(LatticeBuilder& b, int x0, int cells, int front, int back) {
  for (int y = 0; y < cells; ++y)
    b.quad({x0, y, 0}, {x0 + 1, y, 0}, {x0 + 1, y + 1, 0}, {x0, y + 1, 0}, front, back);
}

// The quads of the plane x = 0 for z in [z0, z0 + 1], y in [0, cells], normal +x.
void vertical_strip(LatticeBuilder& b, int z0, int cells, int front, int back) {
  for (int y = 0; y < cells; ++y)
    b.quad({0, y, z0}, {0, y + 1, z0}, {0, y + 1, z0 + 1}, {0, y, z0 + 1}, front, back);
}

}  // namespace

FractureSurface example_sheet(int n, const std::vector<glm::ivec2>& holes) {
  if (n < 2) throw InputError("example_sheet: n = " + std::to_string(n) + ", expected at least 2");
  LatticeBuilder b;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i)
      if (std::find(holes.begin(), holes.end(), glm::ivec2(i, j)) == holes.end())
        b.quad({i, j, 0}, {i + 1, j, 0}, {i + 1, j + 1, 0}, {i, j + 1, 0}, 1, 0);
  return b.build(2);
}

FractureSurface example_t_junction(int cells) {
  LatticeBuilder b;
  horizontal_strip(b, -1, cells, 1, 0);
  horizontal_strip(b, 0, cells, 2, 0);
  vertical_strip(b, 0, cells, 2, 1);
  return b.build(3);
}

FractureSurface example_cross(int cells) {
  LatticeBuilder b;
  horizontal_strip(b, -1, cells, 0, 3);
  horizontal_strip(b, 0, cells, 1, 2);
  vertical_strip(b, 0, cells, 1, 0);
  vertical_strip(b, -1, cells, 2, 3);
  return b.build(4);
}

}  // namespace fracref
