// The materials' own colours (sample_albedo): the phases the paper's pictures show, none for the
// materials without colours of their own, and the same bytes for any thread count.
#include <gtest/gtest.h>

#include <algorithm>

#include "field/procedural.hpp"

namespace fracref {
namespace {

FieldSpec make_spec(const std::string& type) {
  FieldSpec spec;
  spec.type = type;
  spec.object_min = {-1, -1, -0.5};
  spec.object_max = {1, 1, 0.5};
  return spec;
}

Grid3 grid_like(const FieldSpec& spec, glm::uvec3 dims) { return sample_strength(spec, spec.object_min, spec.object_max, dims); }

glm::vec3 colour_at(const std::array<Grid3, 3>& rgb, std::size_t i) {
  return {rgb[0].values[i], rgb[1].values[i], rgb[2].values[i]};
}

TEST(Albedo, ClayBrickAndConstantHaveNoColoursOfTheirOwn) {
  for (const char* type : {"constant", "perlin", "fbm", "brick"}) {
    const FieldSpec spec = make_spec(type);
    EXPECT_FALSE(sample_albedo(spec, grid_like(spec, {4, 4, 3})).has_value()) << type;
  }
}

TEST(Albedo, FruitCubesHaveColoursOfTheirOwnInRedJelly) {
  const FieldSpec spec = make_spec("inclusions");
  const auto cubes = inclusion_cubes(spec);
  // Each cube's centre, then the box's corner, clear of every cube.
  std::vector<glm::dvec3> at;
  for (const InclusionCube& c : cubes) at.push_back(c.centre);
  at.push_back(spec.object_min);
  // Each point as the one node of a grid of its own.
  std::vector<glm::vec3> colours;
  for (const glm::dvec3& p : at) {
    Grid3 one;
    one.dims = {1, 1, 1}, one.origin = p, one.cell = 1.0;
    one.values.assign(1, 0.0f);
    const auto rgb = sample_albedo(spec, one);
    ASSERT_TRUE(rgb.has_value());
    colours.push_back(colour_at(*rgb, 0));
  }
  const glm::vec3 jelly = colours.back();
  EXPECT_GT(jelly.r, 2.0f * jelly.g);  // red
  std::size_t distinct = 0;
  for (std::size_t k = 0; k + 1 < colours.size(); ++k) {
    EXPECT_GT(glm::length(colours[k] - jelly), 0.2f) << "cube " << k;
    distinct += std::none_of(colours.begin(), colours.begin() + std::ptrdiff_t(k),
                             [&](const glm::vec3& c) { return glm::length(c - colours[k]) < 1e-3f; });
  }
  EXPECT_GE(distinct, 4u);  // fruit of several colours
}

TEST(Albedo, MarbleIsWhiteWhereItIsSoftAndBlueWhereItIsHard) {
  const FieldSpec spec = make_spec("marble");
  const Grid3 zeta = grid_like(spec, {16, 16, 8});
  const auto rgb = sample_albedo(spec, zeta);
  ASSERT_TRUE(rgb.has_value());
  int soft = 0, hard = 0;
  for (std::size_t i = 0; i < zeta.values.size(); ++i) {
    const glm::vec3 c = colour_at(*rgb, i);
    if (zeta.values[i] < 0.3f) {  // white
      EXPECT_GT(c.r, 0.6f);
      ++soft;
    }
    if (zeta.values[i] > 0.7f) {  // blue
      EXPECT_GT(c.b, 1.5f * c.r);
      ++hard;
    }
  }
  EXPECT_GT(soft, 50);
  EXPECT_GT(hard, 20);
}

TEST(Albedo, TheSameBytesOnAnyThreadCount) {
  for (const char* type : {"marble", "branch", "wood", "inclusions"}) {
    const FieldSpec spec = make_spec(type);
    const Grid3 like = grid_like(spec, {9, 9, 7});
    const auto one = sample_albedo(spec, like, 1), three = sample_albedo(spec, like, 3);
    ASSERT_TRUE(one && three) << type;
    for (int k = 0; k < 3; ++k) EXPECT_EQ((*one)[k].values, (*three)[k].values) << type;
  }
}

}  // namespace
}  // namespace fracref
