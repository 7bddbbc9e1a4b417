// coarse/fit_labels: the clean-ups of a fitted labelling of a tet lattice.
#include <gtest/gtest.h>

#include <vector>

#include "coarse/fit_labels.hpp"
#include "coarse/tet_lattice.hpp"

namespace fracref::coarse_detail {
namespace {

glm::dvec3 centroid(const TetSet& set, std::uint32_t t) {
  const glm::uvec4 v = set.tets[t];
  return 0.25 * (set.positions[v.x] + set.positions[v.y] + set.positions[v.z] + set.positions[v.w]);
}

// 4³ Kuhn cells over [0, 4]³, label 0 for x < 2 and 1 beyond: a flat interface on cell faces.
struct Halves {
  TetSet set = box_lattice({glm::dvec3(0.0), glm::dvec3(4.0), glm::ivec3(4)});
  InteriorFaces faces = interior_faces(set);
  std::vector<int> label;
  std::vector<int> neighbours = std::vector<int>(set.tets.size(), 0);
  Halves() {
    for (std::uint32_t t = 0; t < set.tets.size(); ++t) label.push_back(centroid(set, t).x < 2.0 ? 0 : 1);
    for (const glm::uvec2& f : faces.tets) ++neighbours[f.x], ++neighbours[f.y];
  }
  // The first tet off the hull (four neighbours) in label l with a face on the interface, if
  // `on_interface`, else with none.
  std::uint32_t tet(int l, bool on_interface) const {
    for (std::uint32_t t = 0; t < set.tets.size(); ++t) {
      if (label[t] != l || neighbours[t] != 4) continue;
      bool across = false;
      for (const glm::uvec2& f : faces.tets)
        if ((f.x == t && label[f.y] != l) || (f.y == t && label[f.x] != l)) across = true;
      if (across == on_interface) return t;
    }
    ADD_FAILURE() << "no such tet";
    return 0;
  }
};

TEST(RelabelNotches, AFlatInterfaceOnTheLatticeStaysAsItIs) {
  Halves h;
  const std::vector<int> before = h.label;
  EXPECT_EQ(relabel_notches(h.set.tets.size(), h.faces, h.label), 0u);
  EXPECT_EQ(h.label, before);
}

TEST(RelabelNotches, ATetStickingIntoTheOtherSideGoesBack) {
  Halves h;
  const std::vector<int> before = h.label;
  // A tet of label 0 on the interface given to 1: a bump of 1 into 0's side, three of its
  // neighbours 0. And a tet deep inside 1 given to 0: an island, all four neighbours 1.
  const std::uint32_t bump = h.tet(0, true), island = h.tet(1, false);
  h.label[bump] = 1, h.label[island] = 0;
  EXPECT_EQ(relabel_notches(h.set.tets.size(), h.faces, h.label), 2u);
  EXPECT_EQ(h.label, before);
}

TEST(RelabelNotches, TetsOnTheHullAreLeftAlone) {
  Halves h;
  std::uint32_t hull = 0;
  while (h.neighbours[hull] == 4 || h.label[hull] != 0) ++hull;
  h.label[hull] = 2;  // a label none of its neighbours has
  const std::vector<int> before = h.label;
  EXPECT_EQ(relabel_notches(h.set.tets.size(), h.faces, h.label), 0u);
  EXPECT_EQ(h.label, before);
}

}  // namespace
}  // namespace fracref::coarse_detail
