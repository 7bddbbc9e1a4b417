// The scene's field.params mapped onto the procedural materials, every error naming the key.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "geom/bvh.hpp"
#include "geom/shapes.hpp"
#include "pipeline/material.hpp"
#include "pipeline/strength.hpp"
#include "util/error.hpp"

using namespace fracref;

namespace {

FieldSettings settings(FieldType type, const char* params) {
  FieldSettings f;
  f.type = type;
  f.resolution = {8, 8, 8};
  f.params = nlohmann::json::parse(params);
  return f;
}

std::string error_of(FieldType type, const char* params) {
  try {
    material_from_scene(settings(type, params), "scene.json", glm::dvec3(0.0), glm::dvec3(1.0));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(PipelineMaterial, ParamsReachTheMaterial) {
  FieldSpec m = material_from_scene(settings(FieldType::marble, R"({"distortion": 3.5, "scale": 0.3})"), "scene.json",
                                    glm::dvec3(0.0), glm::dvec3(2.0));
  EXPECT_EQ(m.type, "marble");
  EXPECT_DOUBLE_EQ(m.marble.distortion, 3.5);
  EXPECT_DOUBLE_EQ(m.scale, 0.3);
  EXPECT_EQ(m.object_max, glm::dvec3(2.0));
  FieldSpec w = material_from_scene(settings(FieldType::branch, R"({"axis": [0, 1, 0]})"), "s.json", glm::dvec3(0.0),
                                    glm::dvec3(1.0));
  EXPECT_EQ(w.wood.axis, glm::dvec3(0.0, 1.0, 0.0));
}

TEST(PipelineMaterial, ErrorsNameTheFileAndKey) {
  std::string e = error_of(FieldType::marble, R"({"distorsion": 1})");
  EXPECT_NE(e.find("scene.json"), std::string::npos) << e;
  EXPECT_NE(e.find("field.params.distorsion"), std::string::npos) << e;
  e = error_of(FieldType::brick, R"({"mortar": "thin"})");
  EXPECT_NE(e.find("field.params.mortar"), std::string::npos) << e;
  e = error_of(FieldType::marble, R"({"edge": -1})");
  EXPECT_NE(e.find("scene.json"), std::string::npos) << e;
  EXPECT_NE(e.find("edge"), std::string::npos) << e;
  e = error_of(FieldType::wood, R"({"grain_frequency": 2})");  // a marble key on wood
  EXPECT_NE(e.find("field.params.grain_frequency"), std::string::npos) << e;
  e = error_of(FieldType::grid, "{}");
  EXPECT_NE(e.find("field.type"), std::string::npos) << e;
}

TEST(PipelineStrength, DistanceAndModifiedField) {
  Grid3 g;
  g.dims = {5, 5, 5};
  g.origin = glm::dvec3(0.0);
  g.cell = 0.25;
  g.values.assign(g.size(), 0.5f);
  // One big triangle in the plane z = 0.5 covering the grid's xy range.
  Grid3 d = distance_grid(g, {{-1, -1, 0.5}, {4, -1, 0.5}, {-1, 4, 0.5}}, {{0, 1, 2}}, 2);
  for (unsigned z = 0; z < 5; ++z) EXPECT_NEAR(d.at(2, 2, z), std::abs(0.25 * z - 0.5), 1e-6) << z;
  WeightsSpec w;
  w.strength = 2.0;
  w.distance = 4.0;
  w.offset = 0.1;
  Grid3 psi = modified_field(g, d, w, 2.0);
  EXPECT_NEAR(psi.at(1, 1, 0), 2.0 * 0.5 + 4.0 * 0.5 / 2.0 + 0.1, 1e-6);
  EXPECT_NEAR(psi.at(1, 1, 2), 2.0 * 0.5 + 0.1, 1e-6);
}

// distance_grid shares candidate lists between nearby nodes; its values must be exactly those of
// the plain definition, the least squared distance to any triangle, on a mesh of uneven
// triangles and a grid reaching far outside it (nodes near it, inside it and far from it).
TEST(PipelineMaterial, DistanceGridEqualsTheNearestTriangleEverywhere) {
  TriangleSoup mesh = make_uv_sphere({0.3, -0.2, 0.1}, 0.8, 9, 14);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  for (auto& p : mesh.positions) p += glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
  Grid3 g;
  g.dims = {13, 10, 11};
  g.origin = glm::dvec3(-2.0, -1.7, -1.9);
  g.cell = 0.37;
  g.values.assign(g.size(), 0.0f);
  const Grid3 d = distance_grid(g, mesh.positions, mesh.triangles, 2);
  for (unsigned z = 0; z < g.dims.z; ++z)
    for (unsigned y = 0; y < g.dims.y; ++y)
      for (unsigned x = 0; x < g.dims.x; ++x) {
        const glm::dvec3 p = g.node_position(x, y, z);
        double best = std::numeric_limits<double>::infinity();
        for (const auto& t : mesh.triangles)
          best = std::min(best, closest_point_on_triangle(p, mesh.positions[t[0]], mesh.positions[t[1]],
                                                          mesh.positions[t[2]]).squared_distance);
        ASSERT_EQ(d.at(x, y, z), float(std::sqrt(best))) << x << " " << y << " " << z;
      }
}
