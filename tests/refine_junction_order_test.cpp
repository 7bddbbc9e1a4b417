// An edge split is refused when it would change the order of the sheets around a junction edge,
// which rebuild_adjacency reads from the geometry to tell the pieces apart.
#include <gtest/gtest.h>

#include "refine/junction_order.hpp"
#include "surface/surface_examples.hpp"

namespace fracref {
namespace {

glm::vec3 at(const FractureSurface& s, std::uint32_t v) { return glm::vec3(s.positions[v]); }

// On the T-junction example (the sheet z = 0, and x = 0 above it): a face of the x > 0 half of
// the flat sheet with an edge on the junction, and one of its other edges (regular).
struct Case {
  std::uint32_t face = 0, edge = 0;
  bool found = false;
};

Case flat_face_at_junction(const FractureSurface& s) {
  for (std::uint32_t g = 0; g < s.edges.size(); ++g) {
    if (s.edge_special[g] != kEdgeNonManifold) continue;
    for (std::uint32_t k = s.ef_offsets[g]; k < s.ef_offsets[g + 1]; ++k) {
      const std::uint32_t f = s.ef_faces[k];
      const glm::uvec4 t = s.faces[f];
      const std::uint32_t z = t.x + t.y + t.z - s.edges[g].x - s.edges[g].y;
      if (at(s, z).z != 0.0f || at(s, z).x <= 0.0f) continue;
      for (int c = 0; c < 3; ++c)
        if (s.edge_special[s.face_edges[3 * f + c]] == kEdgeRegular) return {f, s.face_edges[3 * f + c], true};
    }
  }
  return {};
}

TEST(JunctionOrder, SplitOnItsEdgeKeepsTheOrder) {
  const FractureSurface s = example_t_junction(3);
  const Case c = flat_face_at_junction(s);
  ASSERT_TRUE(c.found);
  const glm::uvec2 e = s.edges[c.edge];
  const SplitRequest r{SplitRequest::kEdge, c.edge, glm::vec3(0.5f, 0.5f, 0.0f)};
  EXPECT_TRUE(split_keeps_junction_order(s, r, 0.5f * (at(s, e.x) + at(s, e.y))));
}

TEST(JunctionOrder, SplitThatTurnsAFacePastAnotherSheetIsRefused) {
  const FractureSurface s = example_t_junction(3);
  const Case c = flat_face_at_junction(s);
  ASSERT_TRUE(c.found);
  const glm::uvec2 e = s.edges[c.edge];
  // The new vertex mirrored to x < 0: the face on the junction edge would turn past the
  // vertical sheet x = 0 into the other half.
  glm::vec3 m = 0.5f * (at(s, e.x) + at(s, e.y));
  m.x = -std::max(m.x, 0.1f);
  m.z = 0.05f;
  EXPECT_FALSE(split_keeps_junction_order(s, {SplitRequest::kEdge, c.edge, glm::vec3(0.5f, 0.5f, 0.0f)}, m));
}

TEST(JunctionOrder, JunctionEdgeSplitAtItsMidpointKeepsTheOrder) {
  const FractureSurface s = example_t_junction(3);
  for (std::uint32_t g = 0; g < s.edges.size(); ++g) {
    if (s.edge_special[g] != kEdgeNonManifold) continue;
    const glm::uvec2 e = s.edges[g];
    EXPECT_TRUE(split_keeps_junction_order(s, {SplitRequest::kEdge, g, glm::vec3(0.5f, 0.5f, 0.0f)},
                                           0.5f * (at(s, e.x) + at(s, e.y))));
  }
}

}  // namespace
}  // namespace fracref
